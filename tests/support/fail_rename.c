// A disk that fails at one path, for tests (LD_PRELOAD): rename() onto the
// path in TREEDYN_TEST_FAIL_RENAME_TO fails with EIO; every other rename is
// the C library's. Lets a test fail an ensemble's output at its very last
// step while its checkpoint, on the same disk, is written as usual.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

int rename(const char* from, const char* to) {
  const char* failing = getenv("TREEDYN_TEST_FAIL_RENAME_TO");
  if (failing != NULL && to != NULL && strcmp(to, failing) == 0) {
    errno = EIO;
    return -1;
  }
  void* symbol = dlsym(RTLD_NEXT, "rename");
  int (*real)(const char*, const char*) = NULL;
  memcpy(&real, &symbol, sizeof real);  // ISO C has no cast from object to function pointer
  return real(from, to);
}
