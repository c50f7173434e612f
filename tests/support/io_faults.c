// A disk seen and failed from inside a run, for tests (LD_PRELOAD into
// treedyn-ensemble, alone or with mpirun and its ranks):
//   TREEDYN_TEST_FAIL_RENAME_TO=PATH   rename() onto PATH fails with EIO, so
//       a test fails an ensemble's output at its very last step while its
//       checkpoint, on the same disk, is written as usual;
//   TREEDYN_TEST_FSYNC_LOG=FILE        each fsync() appends the path of the
//       file or directory it flushes to FILE, one line each (O_APPEND: the
//       lines of several processes do not mix), then flushes it;
//   TREEDYN_TEST_SLOW_FSYNC=TEXT       an fsync() of a path containing TEXT
//       takes 0.5 s more: a slow disk, for a test that the others wait;
//   TREEDYN_TEST_SLOW_WRITE=TEXT       a pwrite() to a path containing TEXT
//       (HDF5 writes its files so) takes 5 ms more: a slow disk under a
//       run's output, for a test of where rank 0's time is counted.
// Every other call is the C library's.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

// The C library's function, as an object pointer: callers copy it into a
// function pointer (ISO C has no cast from one to the other).
static void* next_symbol(const char* name) { return dlsym(RTLD_NEXT, name); }

// The length of the path `fd` is open on, written into `path` (room for
// one more character), or 0.
static size_t path_of(int fd, char* path, size_t size) {
  char link[64];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, path, size - 2);
  if (n <= 0) return 0;
  path[n] = '\0';
  return (size_t)n;
}

// The C library's function, looked up once (every process of a run calls
// pwrite often). Relaxed atomics: threads that race store the same value.
static void* cached_symbol(void** cache, const char* name) {
  void* symbol = __atomic_load_n(cache, __ATOMIC_RELAXED);
  if (symbol == NULL) {
    symbol = next_symbol(name);
    __atomic_store_n(cache, symbol, __ATOMIC_RELAXED);
  }
  return symbol;
}

// pwrite and pwrite64 (which a program built with _FILE_OFFSET_BITS=64
// calls) are one call on the 64-bit targets treedyn builds for.
_Static_assert(sizeof(off_t) == sizeof(off64_t), "pwrite and pwrite64 take offsets of one size");

// TREEDYN_TEST_SLOW_WRITE: 5 ms more for a write into a matching path,
// then the C library's function `name` (cached in `cache`).
static ssize_t slowed_pwrite(void** cache, const char* name, int fd, const void* buffer, size_t count, off64_t offset) {
  const int saved = errno;
  const char* slow = getenv("TREEDYN_TEST_SLOW_WRITE");
  char path[4097];
  if (slow != NULL && path_of(fd, path, sizeof path) > 0 && strstr(path, slow) != NULL) {
    const struct timespec pause = {0, 5000000};
    nanosleep(&pause, NULL);
  }
  errno = saved;
  void* symbol = cached_symbol(cache, name);
  ssize_t (*real)(int, const void*, size_t, off64_t) = NULL;
  memcpy(&real, &symbol, sizeof real);
  return real(fd, buffer, count, offset);
}

ssize_t pwrite(int fd, const void* buffer, size_t count, off_t offset) {
  static void* cache = NULL;
  return slowed_pwrite(&cache, "pwrite", fd, buffer, count, offset);
}

ssize_t pwrite64(int fd, const void* buffer, size_t count, off64_t offset) {
  static void* cache = NULL;
  return slowed_pwrite(&cache, "pwrite64", fd, buffer, count, offset);
}

int rename(const char* from, const char* to) {
  const char* failing = getenv("TREEDYN_TEST_FAIL_RENAME_TO");
  if (failing != NULL && to != NULL && strcmp(to, failing) == 0) {
    errno = EIO;
    return -1;
  }
  void* symbol = next_symbol("rename");
  int (*real)(const char*, const char*) = NULL;
  memcpy(&real, &symbol, sizeof real);
  return real(from, to);
}

int fsync(int fd) {
  const int saved = errno;
  const char* log = getenv("TREEDYN_TEST_FSYNC_LOG");
  const char* slow = getenv("TREEDYN_TEST_SLOW_FSYNC");
  char path[4097];
  const size_t n = path_of(fd, path, sizeof path);
  if (n > 0) {
    if (slow != NULL && strstr(path, slow) != NULL) {
      const struct timespec half = {0, 500000000};
      nanosleep(&half, NULL);
    }
    const int out = log != NULL ? open(log, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644) : -1;
    if (out >= 0) {
      path[n] = '\n';
      if (write(out, path, n + 1) < 0) {
        /* a test's log: nothing to do */
      }
      close(out);
    }
  }
  errno = saved;
  void* symbol = next_symbol("fsync");
  int (*real)(int) = NULL;
  memcpy(&real, &symbol, sizeof real);
  return real(fd);
}
