// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: watch --daemon (see daemon.h).
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "daemon.h"

/* How long an older watcher may take to stop: a save in progress waits up to SW_LOCK_WAIT_MS. */
#define TAKEOVER_MS (SW_LOCK_WAIT_MS + 10000)

/* run_dir exists, is a directory of ours and closed to others (created 0700). */
static int run_dir_ready(const char *dir, struct sw_err *e)
{
	struct stat st;

	if (mkdir(dir, 0700) < 0 && errno != EEXIST)
		return sw_err_set(e, SW_EXIT_IO, "%s: cannot create: %s", dir,
				  strerror(errno));
	if (lstat(dir, &st) < 0)
		return sw_err_set(e, SW_EXIT_IO, "%s: %s", dir, strerror(errno));
	if (!S_ISDIR(st.st_mode))
		return sw_err_set(e, SW_EXIT_PERM,
				  "%s: refused: not a directory (a symbolic link?)",
				  dir);
	if (st.st_uid != geteuid() || (st.st_mode & 0022))
		return sw_err_set(e, SW_EXIT_PERM,
				  "%s: refused: owned by uid %u or writable by others (mode %03o)",
				  dir, (unsigned int)st.st_uid,
				  (unsigned int)(st.st_mode & 0777));
	return SW_EXIT_OK;
}

/* Leave the caller: returns only in the grandchild; the others exit. */
static int detach(struct sw_err *e)
{
	pid_t pid;
	int fd, status;

	fflush(NULL);
	pid = fork();
	if (pid < 0)
		return sw_err_set(e, SW_EXIT_OSERR, "watch --daemon: fork: %s",
				  strerror(errno));
	if (pid > 0) {
		/* The caller: done once the watcher is on its own. */
		if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status))
			_exit(SW_EXIT_OSERR);
		_exit(WEXITSTATUS(status));
	}
	if (setsid() < 0)
		_exit(SW_EXIT_OSERR);
	/* Not a session leader: no controlling terminal can come back. */
	pid = fork();
	if (pid != 0)
		_exit(pid < 0 ? SW_EXIT_OSERR : SW_EXIT_OK);
	if (chdir("/") < 0)
		return sw_err_set(e, SW_EXIT_IO, "watch --daemon: chdir /: %s",
				  strerror(errno));
	/* udev reads the caller's output until every writer has closed it. */
	fd = open("/dev/null", O_RDWR | O_CLOEXEC);
	if (fd < 0 || dup2(fd, STDIN_FILENO) < 0 ||
	    dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0)
		return sw_err_set(e, SW_EXIT_IO, "watch --daemon: /dev/null: %s",
				  strerror(errno));
	if (fd > STDERR_FILENO)
		close(fd);
	return SW_EXIT_OK;
}

static int try_lock(int fd, struct flock *fl)
{
	memset(fl, 0, sizeof(*fl));
	fl->l_type = F_WRLCK;
	fl->l_whence = SEEK_SET;
	return fcntl(fd, F_SETLK, fl);
}

/* Take the lock of key, stopping the watcher that holds it. */
static int take_lock(const char *run_dir, const char *key, struct sw_env *env,
		     struct sw_err *e)
{
	char path[4096], pid[32];
	uint64_t start;
	struct flock fl;
	pid_t old = 0;
	int fd, n;

	snprintf(path, sizeof(path), "%s/%s.watch", run_dir, key);
	fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
	if (fd < 0)
		return sw_err_set(e, errno == ELOOP ? SW_EXIT_PERM : SW_EXIT_IO,
				  "%s: cannot open: %s", path, strerror(errno));
	start = env->now_ms(env->clk);
	while (try_lock(fd, &fl) < 0) {
		if (errno != EAGAIN && errno != EACCES) {
			close(fd);
			return sw_err_set(e, SW_EXIT_IO, "%s: cannot lock: %s",
					  path, strerror(errno));
		}
		if (fcntl(fd, F_GETLK, &fl) == 0 && fl.l_type != F_UNLCK &&
		    fl.l_pid > 0 && fl.l_pid != old) {
			old = fl.l_pid;
			sw_note(env, "watch: replacing the watcher of %s (pid %d)",
				key, (int)old);
			kill(old, SIGTERM);
		}
		if (env->now_ms(env->clk) - start >= TAKEOVER_MS) {
			close(fd);
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: the watcher holding it (pid %d) did not stop within %d s",
					  path, (int)old, TAKEOVER_MS / 1000);
		}
		env->sleep_ms(env->clk, 100);
	}
	/* For people: who watches. The lock, not the content, decides. */
	n = snprintf(pid, sizeof(pid), "%d\n", (int)getpid());
	if (ftruncate(fd, 0) < 0 || pwrite(fd, pid, (size_t)n, 0) != n) {
		close(fd);
		return sw_err_set(e, SW_EXIT_IO, "%s: cannot write: %s", path,
				  strerror(errno));
	}
	/* Kept open (and locked) until the watcher exits. */
	return SW_EXIT_OK;
}

int sw_daemon_start(const char *run_dir, const char *key, struct sw_env *env,
		    struct sw_err *e)
{
	int ret;

	ret = run_dir_ready(run_dir, e);
	if (ret)
		return ret;
	ret = detach(e);
	/* From here on the kernel log is the only one. */
	env->kmsg = true;
	env->tty = false;
	return ret ? ret : take_lock(run_dir, key, env, e);
}
