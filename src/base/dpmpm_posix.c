/* POSIX services that Fortran has no portable binding for: creating one directory with
 * the reason of a failure (errno), flushing a file to the disk, writing a whole file with
 * the reason of a failure, errno itself, whether a
 * path is a directory, the working directory, and noting the stop signals a batch scheduler sends
 * before it kills a job (SIGTERM, SIGUSR1). Used through module dpmpm_posix. */
#include <errno.h>
#include <stddef.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

/* mkdir(path, 0777) without a shell: 0 when the directory was made or already exists,
 * otherwise the errno of the failure (ENOTDIR when path exists and is no directory). */
int dpmpm_mkdir(const char *path)
{
  struct stat st;
  int err;
  if (mkdir(path, 0777) == 0) return 0;
  err = errno;
  if (err == EEXIST) {
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return 0;
    return ENOTDIR;
  }
  return err;
}

/* Flush a file (or a directory: the names in it) to the disk: 0, or the errno of the
 * failure. Used before and after the rename that makes a new checkpoint the current one. */
int dpmpm_fsync(const char *path)
{
  int fd, err = 0;
  fd = open(path, O_RDONLY);
  if (fd < 0) return errno;
  if (fsync(fd) != 0) err = errno;
  close(fd);
  return err;
}

/* The system's text for an errno value. */
const char *dpmpm_strerror(int err) { return strerror(err); }

/* errno as it is now, and setting it to 0: a library call that fails without giving its
 * reason (HDF5's writes) leaves the reason of the system call under it there. */
int dpmpm_errno(void) { return errno; }
void dpmpm_clear_errno(void) { errno = 0; }

/* Write the n bytes at text to path (created or truncated), every byte or an error: 0, or
 * the errno of the first failure (open, a short write, close). */
int dpmpm_write_file(const char *path, const char *text, size_t n)
{
  int fd, err = 0;
  ssize_t w;
  fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) return errno;
  while (n > 0) {
    w = write(fd, text, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      err = errno;
      break;
    }
    if (w == 0) {
      err = EIO;
      break;
    }
    text += w;
    n -= (size_t)w;
  }
  if (close(fd) != 0 && err == 0) err = errno;
  return err;
}

/* 1 when path names a directory (following links), else 0. */
int dpmpm_is_directory(const char *path)
{
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The last stop signal received, 0 before any. A handler may only set a flag of this
 * type; the run loop looks at it between steps. */
static volatile sig_atomic_t stop_signal = 0;

static void note_stop_signal(int sig) { stop_signal = sig; }

/* Catch SIGTERM and SIGUSR1 from now on: each only sets the flag. 0 on success. */
int dpmpm_catch_stop_signals(void)
{
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = note_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  if (sigaction(SIGTERM, &sa, NULL) != 0) return -1;
  if (sigaction(SIGUSR1, &sa, NULL) != 0) return -1;
  return 0;
}

/* The stop signal received so far (0: none). */
int dpmpm_stop_signal(void) { return stop_signal; }

/* Name of a stop signal for messages. */
const char *dpmpm_signal_name(int sig)
{
  if (sig == SIGTERM) return "SIGTERM";
  if (sig == SIGUSR1) return "SIGUSR1";
  return "a signal";
}

/* The working directory into buf (n bytes, NUL-terminated): 0, or the errno of the
 * failure (ERANGE when it does not fit). */
int dpmpm_getcwd(char *buf, size_t n)
{
  if (getcwd(buf, n) == NULL) return errno;
  return 0;
}
