/* mfcd: the freed small blocks at the top of the heap go back to the system (heap_m).
 *
 * Blocks under glibc's mmap threshold (128 kB, memory_policy_m) come from the heap; freed,
 * their pages stay the process's until the free space at the heap's top is trimmed, which
 * glibc does on a free only past its trim threshold and only from the very top. A builder
 * that allocates and frees many small blocks (the 3D tables' per-cell rows, some 17 kB
 * each, a block of 4096 cells at a time) leaves tens of MB resident that way when a live
 * block sits above them, and they then count in the build's peak. malloc_trim(0) returns
 * every free page of the heap, not only the top's. Other C libraries: nothing.
 */
#include <stdlib.h> /* (defines __GLIBC__ under glibc) */
#ifdef __GLIBC__
#include <malloc.h>
#endif

/* Returns 1 when memory was given back, 0 otherwise. */
int mfcd_heap_return(void)
{
#ifdef __GLIBC__
    return malloc_trim(0);
#else
    return 0;
#endif
}
