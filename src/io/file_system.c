/* mfcd: files read once, and the file systems output may go to (file_system_m).
 *
 * mfcd_open_regular opens a file for reading without blocking (a FIFO with no writer
 * would block the open) and says what it is from the open descriptor, so the bytes read
 * are those of the file checked: a plain file of a bounded size, never a FIFO, device,
 * directory or socket. mfcd_fs_refuses says whether a directory lies on a file system no
 * run can write its output to (read-only, or a kernel's pseudo file system such as /proc),
 * which write permission alone does not tell for root.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statfs.h>
#include <sys/statvfs.h>
#include <unistd.h>

/* What a path is, as mfcd_open_regular reports it. */
enum { kind_regular = 0, kind_directory = 1, kind_fifo = 2, kind_char_device = 3,
       kind_block_device = 4, kind_socket = 5, kind_other = 6, kind_link = 7 };

/* Open path for reading without blocking and, when nofollow is set, without following a
 * symbolic link as its last component (a link is reported as kind_link: a deck cannot point
 * mfcd at another file through a link named like a script), and say from the open descriptor what it is (*kind,
 * above) and its size in bytes (*size, 64-bit). Returns the descriptor when it is a plain
 * file of at most max_bytes bytes; otherwise -1, with *kind and *size set when the open
 * succeeded, and *err_no the open's errno when it did not (0 otherwise). */
int mfcd_open_regular(const char *path, int nofollow, long long max_bytes, long long *size,
                      int *kind, int *err_no)
{
  struct stat st;
  int fd;
  *size = -1;
  *kind = kind_other;
  *err_no = 0;
  fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC | (nofollow ? O_NOFOLLOW : 0));
  if (fd < 0) {
    if (errno == ELOOP) {
      *kind = kind_link;
      return -1;
    }
    *err_no = errno;
    return -1;
  }
  if (fstat(fd, &st) != 0) {
    *err_no = errno;
    close(fd);
    return -1;
  }
  *size = (long long)st.st_size;
  if (S_ISREG(st.st_mode)) *kind = kind_regular;
  else if (S_ISDIR(st.st_mode)) *kind = kind_directory;
  else if (S_ISFIFO(st.st_mode)) *kind = kind_fifo;
  else if (S_ISCHR(st.st_mode)) *kind = kind_char_device;
  else if (S_ISBLK(st.st_mode)) *kind = kind_block_device;
  else if (S_ISSOCK(st.st_mode)) *kind = kind_socket;
  if (*kind != kind_regular || *size > max_bytes) {
    close(fd);
    return -1;
  }
  return fd;
}

/* Read up to n bytes from fd into buf, until n or the end of the file: the count read, or
 * -errno. */
long long mfcd_read_fd(int fd, char *buf, long long n)
{
  long long got = 0;
  while (got < n) {
    ssize_t r = read(fd, buf + got, (size_t)(n - got));
    if (r < 0) {
      if (errno == EINTR) continue;
      return -(long long)errno;
    }
    if (r == 0) break;
    got += r;
  }
  return got;
}

/* Whether directory path is on a file system output cannot go to: 1 read-only, 2 a pseudo
 * file system of the kernel (proc, sysfs, cgroup, debugfs, tracefs, securityfs, devpts,
 * bpf, configfs, pstore, efivarfs), 0 otherwise or when it cannot tell. */
int mfcd_fs_refuses(const char *path)
{
  struct statvfs v;
  struct statfs f;
  static const long pseudo[] = {
    0x9fa0,      /* proc */
    0x62656572,  /* sysfs */
    0x27e0eb,    /* cgroup */
    0x63677270,  /* cgroup2 */
    0x64626720,  /* debugfs */
    0x74726163,  /* tracefs */
    0x73636673,  /* securityfs */
    0x1cd1,      /* devpts */
    0xcafe4a11,  /* bpf */
    0x62656570,  /* configfs */
    0x6165676c,  /* pstore */
    0xde5e81e4,  /* efivarfs */
  };
  size_t k;
  if (statfs(path, &f) == 0) {
    for (k = 0; k < sizeof pseudo / sizeof pseudo[0]; k++)
      if ((long)f.f_type == pseudo[k]) return 2;
  }
  if (statvfs(path, &v) == 0 && (v.f_flag & ST_RDONLY)) return 1;
  return 0;
}

/* 1 when standard output and standard error are the same file (a terminal, or a batch
 * log that takes both), so a message written to both would be read twice; 0 otherwise. */
int mfcd_same_out_err(void)
{
    struct stat a, b;
    if (fstat(1, &a) != 0 || fstat(2, &b) != 0) return 0;
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}
