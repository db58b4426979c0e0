/* mfcd: freed memory goes back to the system (memory_policy_m).
 *
 * glibc serves a block of 128 kB or more from a mapping of its own, returned to the system
 * when freed, but it raises that threshold to the size of each such block freed (up to
 * 32 MB), so that after the first large free, blocks of a few MB come from the heap, where
 * their pages stay the process's after they are freed. mfcd frees whole-body arrays of a
 * few MB each before it allocates a rank's part (mpi_domain_m), and those pages then count
 * in every rank's peak. Setting the threshold fixes it at 128 kB (glibc's default, no longer
 * adjusted), and glibc's heap trimming keeps its own default. A user's MALLOC_MMAP_THRESHOLD_
 * is kept as it is; other C libraries are left alone.
 */
#include <stdlib.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

/* Returns 1 when the threshold was set, 0 when left as it is. */
int mfcd_memory_policy(void)
{
#ifdef __GLIBC__
    if (getenv("MALLOC_MMAP_THRESHOLD_") != NULL)
        return 0;
    return mallopt(M_MMAP_THRESHOLD, 128 * 1024) == 1;
#else
    return 0;
#endif
}

/* Free pages of every heap and arena returned to the system (glibc's malloc_trim, which
 * also releases whole free pages inside a heap): after gmsh has meshed in its own thread,
 * whose arena keeps the pages of its many small blocks freed. Returns 1 when some memory
 * was released, 0 otherwise or without glibc. */
int mfcd_memory_trim(void)
{
#ifdef __GLIBC__
    return malloc_trim(0);
#else
    return 0;
#endif
}

/* The bytes glibc holds in blocks mapped apart (mallinfo2's hblkhd), for the test that the
 * policy holds; -1 without glibc 2.33 or later. */
long long mfcd_mapped_bytes(void)
{
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    struct mallinfo2 mi = mallinfo2();
    return (long long)mi.hblkhd;
#else
    return -1;
#endif
}
