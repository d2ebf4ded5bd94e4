/* Loaded with LD_PRELOAD into the ranks of a run (tests/check_flush_kill.py): stops one rank
 * (SIGSTOP) right before its first write to a chosen file after its N-th call of H5Fflush,
 * so that a kill of the job lands at a chosen place inside one of HDF5's metadata flushes,
 * the same place on every run. The environment says where:
 *   DPMPM_STOP_FILE   the end of the path of the file watched (e.g. "/out/kill.h5")
 *   DPMPM_STOP_RANK   the rank stopped (OMPI_COMM_WORLD_RANK or PMI_RANK), 0 if unset
 *   DPMPM_STOP_FLUSH  N, counted over every H5Fflush call of that rank
 *   DPMPM_STOP_FLAG   a file made just before the stop, for the test to wait on
 * Without DPMPM_STOP_FILE nothing is watched. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long nflush = 0;
static int armed = 0;

/* This process is the rank to stop. */
static int chosen_rank(void)
{
  const char *want = getenv("DPMPM_STOP_RANK");
  const char *rank = getenv("OMPI_COMM_WORLD_RANK");
  if (!rank) rank = getenv("PMI_RANK");
  if (!rank) return 0;
  return strcmp(rank, want ? want : "0") == 0;
}

/* fd is open on the watched file. */
static int watched(int fd)
{
  const char *suffix = getenv("DPMPM_STOP_FILE");
  char link[64], path[4096];
  ssize_t n;
  size_t ls;
  if (!suffix) return 0;
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  n = readlink(link, path, sizeof path - 1);
  if (n < 0) return 0;
  path[n] = 0;
  ls = strlen(suffix);
  return (size_t)n >= ls && strcmp(path + n - ls, suffix) == 0;
}

/* Before every write: the stop, once armed, at the first write to the watched file. */
static void before_write(int fd)
{
  const char *flag;
  FILE *f;
  if (!armed || !watched(fd)) return;
  armed = 0;
  flag = getenv("DPMPM_STOP_FLAG");
  if (flag && (f = fopen(flag, "w")) != NULL) fclose(f);
  raise(SIGSTOP);
}

/* H5Fflush(hid_t, H5F_scope_t), counted on the chosen rank. */
int H5Fflush(int64_t obj, int scope)
{
  static int (*real)(int64_t, int);
  const char *n = getenv("DPMPM_STOP_FLUSH");
  if (!real) real = (int (*)(int64_t, int))dlsym(RTLD_NEXT, "H5Fflush");
  if (getenv("DPMPM_STOP_FILE") && n && chosen_rank() && ++nflush == atol(n)) armed = 1;
  return real(obj, scope);
}

ssize_t pwrite(int fd, const void *buf, size_t count, off_t offset)
{
  static ssize_t (*real)(int, const void *, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t, off_t))dlsym(RTLD_NEXT, "pwrite");
  before_write(fd);
  return real(fd, buf, count, offset);
}

ssize_t pwrite64(int fd, const void *buf, size_t count, off_t offset)
{
  static ssize_t (*real)(int, const void *, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t, off_t))dlsym(RTLD_NEXT, "pwrite64");
  before_write(fd);
  return real(fd, buf, count, offset);
}

ssize_t pwritev(int fd, const struct iovec *iov, int iovcnt, off_t offset)
{
  static ssize_t (*real)(int, const struct iovec *, int, off_t);
  if (!real) real = (ssize_t(*)(int, const struct iovec *, int, off_t))dlsym(RTLD_NEXT, "pwritev");
  before_write(fd);
  return real(fd, iov, iovcnt, offset);
}

ssize_t write(int fd, const void *buf, size_t count)
{
  static ssize_t (*real)(int, const void *, size_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t))dlsym(RTLD_NEXT, "write");
  before_write(fd);
  return real(fd, buf, count);
}
