/* mfcd: the confined thread (confine_m).
 *
 * mfcd_confined_run runs one task (a C-callable function of one pointer) in a thread of its
 * own, under a seccomp filter that holds for that thread alone and ends with it: the task
 * can read files, but it creates, changes, renames or removes none, makes no directory,
 * changes no directory, starts no process (execve, fork, vfork, clone without
 * CLONE_THREAD), opens no socket, reads nothing from standard input and uses none of the
 * ways around such a filter (io_uring, file handles, another architecture's system calls).
 * What the filter refuses fails with an error code (EACCES, EPERM, EBADF or ENOSYS), as it
 * would for a user without the right, so the task sees a failure, never a crash.
 * While the task runs, the working directory is / (a relative path it opens names nothing
 * of the user's, such as a configuration file planted beside a deck) and HOME is
 * /dev/null (no file under the user's home is read or written); afterwards the working
 * directory, HOME, PATH, PYTHONPATH, the locale, the signal dispositions and the stack
 * limit are as before, whatever the task changed of them (all are the process's, not the
 * thread's).
 * The calling thread meanwhile watches the task: past the wall-clock limit, or when the
 * process's resident memory has grown by more than the memory limit since the task
 * started, it writes the caller's message and ends the process with exit code 2 (bad
 * input: nothing has been written yet when mfcd meshes, and a running task cannot be
 * stopped safely any other way). A crash meanwhile (SIGSEGV, SIGBUS, SIGILL, SIGFPE,
 * SIGABRT: a mesher may abort on a geometry it cannot handle) ends the process the same
 * way, with the caller's crash message, instead of with a core dump.
 * mfcd runs gmsh this way (src/setup/gmsh_mesh_m.f90): gmsh is a large C++ library with a GUI
 * toolkit, PETSc and plugins linked in, and this is what keeps its side effects out of
 * the user's file system whatever it does (doc/deck.md, "What a gmsh script can do").
 *
 * Linux only (x86-64 and AArch64 filters); elsewhere mfcd_confined_run reports ENOSYS and
 * mfcd refuses to start gmsh.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <locale.h>
#include <pthread.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#if defined(__linux__) && (defined(__x86_64__) || defined(__aarch64__))
#define MFCD_HAVE_FILTER 1
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#endif

/* the task's state, written by the task's thread, read by the watcher */
enum { task_running = 0, task_done = 1, task_unconfined = 2 };

struct mfcd_job {
  void (*fn)(void *);
  void *arg;
  int state;
  int error;
};

#ifdef MFCD_HAVE_FILTER

#if defined(__x86_64__)
#define MFCD_AUDIT_ARCH AUDIT_ARCH_X86_64
#else
#define MFCD_AUDIT_ARCH AUDIT_ARCH_AARCH64
#endif

/* A filter under construction: n instructions of at most max_insns. */
#define max_insns 512
struct prog {
  struct sock_filter f[max_insns];
  unsigned short n;
  int overflow;
};

static void emit(struct prog *p, struct sock_filter s)
{
  if (p->n >= max_insns) {
    p->overflow = 1;
    return;
  }
  p->f[p->n++] = s;
}

#define LD_NR BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, nr))
/* the low 32 bits of argument k (little-endian: flags, file descriptors and clone flags
 * all fit there) */
#define LD_ARG(k) BPF_STMT(BPF_LD | BPF_W | BPF_ABS, \
  offsetof(struct seccomp_data, args) + 8 * (k))
#define RET_ERRNO(e) BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | ((e) & SECCOMP_RET_DATA))
#define RET_ALLOW BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW)

/* system call nr fails with errno e (the accumulator holds nr) */
static void refuse(struct prog *p, long nr, int e)
{
  emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, (uint32_t)nr, 0, 1));
  emit(p, (struct sock_filter)RET_ERRNO(e));
}

/* system call nr fails with errno e when argument k has one of the bits of mask set
 * (when_set) or none of them (!when_set); otherwise it is allowed */
static void refuse_bits(struct prog *p, long nr, int k, uint32_t mask, int when_set, int e)
{
  emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, (uint32_t)nr, 0, 4));
  emit(p, (struct sock_filter)LD_ARG(k));
  if (when_set)
    emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JSET | BPF_K, mask, 0, 1));
  else
    emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JSET | BPF_K, mask, 1, 0));
  emit(p, (struct sock_filter)RET_ERRNO(e));
  emit(p, (struct sock_filter)RET_ALLOW);
}

/* system call nr fails with errno e when argument k equals value; otherwise allowed */
static void refuse_equal(struct prog *p, long nr, int k, uint32_t value, int e)
{
  emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, (uint32_t)nr, 0, 4));
  emit(p, (struct sock_filter)LD_ARG(k));
  emit(p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, value, 0, 1));
  emit(p, (struct sock_filter)RET_ERRNO(e));
  emit(p, (struct sock_filter)RET_ALLOW);
}

#ifndef __O_TMPFILE
#define __O_TMPFILE 020000000
#endif
/* open flags that write, create, truncate or append */
#define WRITE_FLAGS ((uint32_t)(O_WRONLY | O_RDWR | O_CREAT | O_TRUNC | O_APPEND | __O_TMPFILE))

/* The filter of the calling thread (and of threads it starts): see the file's header. */
static int confine_this_thread(void)
{
  static struct prog p;
  struct sock_fprog fprog;
  memset(&p, 0, sizeof p);
  emit(&p, (struct sock_filter)BPF_STMT(BPF_LD | BPF_W | BPF_ABS,
    offsetof(struct seccomp_data, arch)));
  emit(&p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, MFCD_AUDIT_ARCH, 1, 0));
  emit(&p, (struct sock_filter)RET_ERRNO(ENOSYS));
  emit(&p, (struct sock_filter)LD_NR);
#if defined(__x86_64__)
  /* the x32 ABI's numbers, outside the table below */
  emit(&p, (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JGE | BPF_K, 0x40000000u, 0, 1));
  emit(&p, (struct sock_filter)RET_ERRNO(ENOSYS));
#endif

  /* files opened for writing, created, truncated or appended to */
#ifdef SYS_open
  refuse_bits(&p, SYS_open, 1, WRITE_FLAGS, 1, EACCES);
#endif
  refuse_bits(&p, SYS_openat, 2, WRITE_FLAGS, 1, EACCES);
#ifdef SYS_openat2
  refuse(&p, SYS_openat2, ENOSYS);   /* its flags are behind a pointer */
#endif
#ifdef SYS_creat
  refuse(&p, SYS_creat, EACCES);
#endif
  /* standard input is never read */
  refuse_equal(&p, SYS_read, 0, 0, EBADF);
  refuse_equal(&p, SYS_readv, 0, 0, EBADF);
  refuse_equal(&p, SYS_pread64, 0, 0, EBADF);
  refuse_equal(&p, SYS_preadv, 0, 0, EBADF);
#ifdef SYS_preadv2
  refuse_equal(&p, SYS_preadv2, 0, 0, EBADF);
#endif
  /* threads only: no process (posix_spawn and system() clone without CLONE_THREAD) */
  refuse_bits(&p, SYS_clone, 0, CLONE_THREAD, 0, EPERM);
#ifdef SYS_clone3
  refuse(&p, SYS_clone3, ENOSYS);   /* its flags are behind a pointer; glibc then uses clone */
#endif
#ifdef SYS_fork
  refuse(&p, SYS_fork, EPERM);
#endif
#ifdef SYS_vfork
  refuse(&p, SYS_vfork, EPERM);
#endif
  refuse(&p, SYS_execve, EPERM);
#ifdef SYS_execveat
  refuse(&p, SYS_execveat, EPERM);
#endif

  {
    /* the file system changed without an open, and the ways around the filter */
    static const long eperm[] = {
#ifdef SYS_mkdir
      SYS_mkdir,
#endif
#ifdef SYS_rmdir
      SYS_rmdir,
#endif
#ifdef SYS_unlink
      SYS_unlink,
#endif
#ifdef SYS_rename
      SYS_rename,
#endif
#ifdef SYS_link
      SYS_link,
#endif
#ifdef SYS_symlink
      SYS_symlink,
#endif
#ifdef SYS_mknod
      SYS_mknod,
#endif
#ifdef SYS_chmod
      SYS_chmod,
#endif
#ifdef SYS_chown
      SYS_chown,
#endif
#ifdef SYS_lchown
      SYS_lchown,
#endif
#ifdef SYS_utime
      SYS_utime,
#endif
#ifdef SYS_utimes
      SYS_utimes,
#endif
#ifdef SYS_futimesat
      SYS_futimesat,
#endif
#ifdef SYS_renameat
      SYS_renameat,
#endif
      SYS_mkdirat, SYS_unlinkat, SYS_renameat2, SYS_linkat, SYS_symlinkat, SYS_mknodat,
      SYS_fchmod, SYS_fchmodat, SYS_fchown, SYS_fchownat, SYS_truncate, SYS_ftruncate,
      SYS_fallocate, SYS_utimensat, SYS_setxattr, SYS_lsetxattr, SYS_fsetxattr,
      SYS_removexattr, SYS_lremovexattr, SYS_fremovexattr, SYS_chdir, SYS_fchdir,
      SYS_chroot, SYS_mount, SYS_umount2, SYS_pivot_root, SYS_swapon, SYS_swapoff,
      SYS_name_to_handle_at, SYS_open_by_handle_at, SYS_unshare, SYS_setns,
      SYS_socket, SYS_socketpair, SYS_connect, SYS_bind, SYS_kill, SYS_ptrace,
      SYS_process_vm_writev, SYS_bpf, SYS_userfaultfd, SYS_perf_event_open,
      SYS_io_uring_setup, SYS_io_uring_enter, SYS_io_uring_register,
      SYS_acct, SYS_reboot, SYS_sethostname, SYS_setdomainname, SYS_init_module,
      SYS_finit_module, SYS_delete_module, SYS_kexec_load,
    };
    size_t k;
    for (k = 0; k < sizeof eperm / sizeof eperm[0]; k++) refuse(&p, eperm[k], EPERM);
  }
  emit(&p, (struct sock_filter)RET_ALLOW);
  if (p.overflow) {
    errno = E2BIG;
    return -1;
  }
  /* both settings are the calling thread's: the caller's own threads keep theirs */
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) return -1;
  fprog.len = p.n;
  fprog.filter = p.f;
  if (prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &fprog, 0, 0) != 0) return -1;
  return 0;
}
#else
static int confine_this_thread(void)
{
  errno = ENOSYS;
  return -1;
}
#endif

static void *run_job(void *p)
{
  struct mfcd_job *job = p;
  if (confine_this_thread() != 0) {
    job->error = errno;
    __atomic_store_n(&job->state, task_unconfined, __ATOMIC_SEQ_CST);
    return NULL;
  }
  job->fn(job->arg);
  __atomic_store_n(&job->state, task_done, __ATOMIC_SEQ_CST);
  return NULL;
}

/* The process's resident memory in bytes (/proc/self/statm), -1 if unknown. */
static long long resident_bytes(void)
{
  char buf[128];
  long long pages_total = 0, pages_resident = 0;
  ssize_t n;
  int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  n = read(fd, buf, sizeof buf - 1);
  close(fd);
  if (n <= 0) return -1;
  buf[n] = '\0';
  {
    char *s = buf, *end;
    pages_total = strtoll(s, &end, 10);
    if (end == s) return -1;
    s = end;
    pages_resident = strtoll(s, &end, 10);
    if (end == s) return -1;
  }
  (void)pages_total;
  return pages_resident * (long long)sysconf(_SC_PAGESIZE);
}

static double seconds_since(const struct timespec *t0)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)(t.tv_sec - t0->tv_sec) + 1.0e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

/* write all of s to fd (a signal or a short write may cut it) */
static void write_all(int fd, const char *s, size_t n)
{
  while (n > 0) {
    ssize_t w = write(fd, s, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return;
    }
    s += w;
    n -= (size_t)w;
  }
}

/* The message a crash during the task ends the process with (the signal handler can use
 * nothing but what is set before it runs); set by mfcd_confined_run for one task at a
 * time. */
static const char *crash_message = "the task crashed";
static size_t crash_length = 16;

static void stop_process(const char *message, size_t len);

/* A crash while the task runs: the crash message, exit code 2 (write and _exit are
 * async-signal-safe). */
static void on_crash(int sig)
{
  (void)sig;
  stop_process(crash_message, crash_length);
}

/* The watcher's end of a task past its limits: the message as mfcd's program writes an
 * error (stderr) and the log's last line (stdout), then exit code 2 at once. */
static void stop_process(const char *message, size_t len)
{
  static const char e1[] = "mfcd: error: ";
  static const char o1[] = "mfcd: bad input (exit 2), nothing written: ";
  write_all(2, e1, sizeof e1 - 1);
  write_all(2, message, len);
  write_all(2, "\n", 1);
  write_all(1, o1, sizeof o1 - 1);
  write_all(1, message, len);
  write_all(1, "\n", 1);
  _exit(2);
}

/* What the task may change of the process and mfcd_confined_run puts back. */
#define n_signals 32
struct process_state {
  int cwd;
  char *home, *path, *pythonpath, *locale;
  struct sigaction act[n_signals];
  int have_act[n_signals];
  struct rlimit stack;
  int have_stack;
};

static char *copy_env(const char *name)
{
  const char *v = getenv(name);
  return v ? strdup(v) : NULL;
}

static void put_env(const char *name, char *value)
{
  if (value) {
    setenv(name, value, 1);
    free(value);
  } else {
    unsetenv(name);
  }
}

/* Keep the process state, then enter the task's: / as the working directory, HOME
 * /dev/null. Returns 0, or an errno when the working directory cannot be kept. */
static int enter_task_state(struct process_state *s)
{
  const char *loc;
  int k;
  s->cwd = open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (s->cwd < 0) return errno;
  s->home = copy_env("HOME");
  s->path = copy_env("PATH");
  s->pythonpath = copy_env("PYTHONPATH");
  loc = setlocale(LC_ALL, NULL);
  s->locale = loc ? strdup(loc) : NULL;
  for (k = 1; k < n_signals; k++)
    s->have_act[k] = sigaction(k, NULL, &s->act[k]) == 0;
  s->have_stack = getrlimit(RLIMIT_STACK, &s->stack) == 0;
  if (chdir("/") != 0) {
    int e = errno;
    close(s->cwd);
    return e;
  }
  setenv("HOME", "/dev/null", 1);
  return 0;
}

static void leave_task_state(struct process_state *s)
{
  int k;
  if (fchdir(s->cwd) != 0) {
    /* the directory was removed meanwhile: nothing better to go back to */
  }
  close(s->cwd);
  put_env("HOME", s->home);
  put_env("PATH", s->path);
  put_env("PYTHONPATH", s->pythonpath);
  if (s->locale) {
    setlocale(LC_ALL, s->locale);
    free(s->locale);
  }
  for (k = 1; k < n_signals; k++)
    if (s->have_act[k] && k != SIGKILL && k != SIGSTOP) sigaction(k, &s->act[k], NULL);
  if (s->have_stack) setrlimit(RLIMIT_STACK, &s->stack);
}

/* Run fn(arg) in a confined thread (the file's header) and wait for it, for at most
 * seconds of wall-clock time and max_growth bytes of resident memory growth (<= 0: no
 * memory limit); past either, write msg_time or msg_memory (of lengths len_time,
 * len_memory) and end the process with exit code 2; on a crash meanwhile, the same with
 * msg_crash. stack_bytes is the thread's stack.
 * Returns 0 when the task ran to its end; otherwise the task did not run at all and the
 * return value is an errno (ENOSYS: no filter on this system; others from prctl or
 * pthread_create). */
int mfcd_confined_run(void (*fn)(void *), void *arg, double seconds, long long max_growth,
                      long long stack_bytes, const char *msg_time, int len_time,
                      const char *msg_memory, int len_memory, const char *msg_crash,
                      int len_crash)
{
  static const int crash_signals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
  struct sigaction crash;
  size_t k;
  struct mfcd_job job;
  pthread_t thread;
  pthread_attr_t attr;
  struct timespec t0, nap;
  struct process_state saved;
  long long rss0;
  int rc, state;
  job.fn = fn;
  job.arg = arg;
  job.state = task_running;
  job.error = 0;
  rss0 = resident_bytes();
  clock_gettime(CLOCK_MONOTONIC, &t0);
  if (pthread_attr_init(&attr) != 0) return EAGAIN;
  if (stack_bytes > 0) pthread_attr_setstacksize(&attr, (size_t)stack_bytes);
  rc = enter_task_state(&saved);
  if (rc != 0) {
    pthread_attr_destroy(&attr);
    return rc;
  }
  /* the handlers are the process's: leave_task_state puts the previous ones back */
  crash_message = msg_crash;
  crash_length = (size_t)len_crash;
  memset(&crash, 0, sizeof crash);
  crash.sa_handler = on_crash;
  sigemptyset(&crash.sa_mask);
  for (k = 0; k < sizeof crash_signals / sizeof crash_signals[0]; k++)
    sigaction(crash_signals[k], &crash, NULL);
  rc = pthread_create(&thread, &attr, run_job, &job);
  pthread_attr_destroy(&attr);
  if (rc != 0) {
    leave_task_state(&saved);
    return rc;
  }
  nap.tv_sec = 0;
  nap.tv_nsec = 10 * 1000 * 1000;   /* 10 ms: a limit is met within a hundredth */
  for (;;) {
    state = __atomic_load_n(&job.state, __ATOMIC_SEQ_CST);
    if (state != task_running) break;
    nanosleep(&nap, NULL);
    if (seconds_since(&t0) > seconds) stop_process(msg_time, (size_t)len_time);
    if (max_growth > 0 && rss0 >= 0) {
      long long rss = resident_bytes();
      if (rss >= 0 && rss - rss0 > max_growth) stop_process(msg_memory, (size_t)len_memory);
    }
  }
  pthread_join(thread, NULL);
  leave_task_state(&saved);
  if (state == task_unconfined) return job.error != 0 ? job.error : ENOSYS;
  return 0;
}

/* The text of errno e (strerror_r's GNU form), copied into buf of n bytes. */
void mfcd_errno_text(int e, char *buf, int n)
{
  const char *s;
  if (n <= 0) return;
  s = strerror_r(e, buf, (size_t)n);
  if (s != buf) {
    strncpy(buf, s, (size_t)n - 1);
    buf[n - 1] = '\0';
  }
}
