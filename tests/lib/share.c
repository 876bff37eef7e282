// SPDX-License-Identifier: MIT
/* Several programs on one card: the checks (share.h). */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "share.h"

double share_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

struct sh2000 *share_open(const char *dev, char *msg, size_t len)
{
	struct sh2000 *h = NULL;

	if (sh2000_open(&h, dev, msg, len) < 0)
		return NULL;
	/* real time on a loaded 2-core machine */
	sh2000_set_heartbeat_limit(h, 2000000000ull);
	return h;
}

static void note_error(struct share_tally *t, struct sh2000 *h, int r)
{
	if (!t->errors++) {
		t->first_error = r;
		snprintf(t->msg, sizeof(t->msg), "%s", sh2000_last_error(h));
	}
}

static int one_command(struct sh2000 *h, unsigned int c, unsigned int i,
		       double *set, struct share_tally *t)
{
	unsigned int axis = c % SH2000_AXES;
	unsigned int param = c < SH2000_AXES ? SH2000_P_KP : SH2000_P_TD;
	double v;
	int r;

	switch (i % 4) {
	case 0:
		/* values a stable loop takes (kp up to 1 count/code, td up
		 * to the default 4 ms): the axes are enabled between the
		 * sets, and with td up to 1 s an axis left where a motion
		 * ended ran its carriage away by millimetres into a
		 * following-error fault, which failed every later enable */
		v = (double)(float)((param == SH2000_P_TD ? 4e-6 : 0.001) *
				    (rand() % 1000 + 1) + c * 1e-6);
		r = sh2000_param_set(h, (int)axis, param, v);
		if (!r)
			*set = v;
		return r;
	case 1:
		r = sh2000_param_get(h, (int)axis, param, &v);
		if (!r && v != *set)
			t->wrong++;
		return r;
	case 2:
		return sh2000_nop(h);
	default:
		if (c >= SH2000_AXES)
			return sh2000_nop(h);
		if ((i / 4) % 2)
			return sh2000_disable(h, 1u << axis);
		return sh2000_enable(h, 1u << axis);
	}
}

/* One process: its tally to out, then exit. */
static void worker(const char *dev, unsigned int c, unsigned int commands,
		   int out)
{
	struct share_tally t = { 0 };
	struct sh2000 *h = share_open(dev, t.msg, sizeof(t.msg));
	double set = 0.0;
	unsigned int i;

	srand(c + 1);
	for (i = 0; h && i < commands; i++) {
		double t0 = share_now_ms();
		int r = one_command(h, c, i, &set, &t);

		if (r < 0)
			note_error(&t, h, r);
		if (share_now_ms() - t0 > t.max_ms)
			t.max_ms = share_now_ms() - t0;
		t.done++;
	}
	if (!h)
		t.errors = 1;
	sh2000_close(h);
	_exit(write(out, &t, sizeof(t)) == (ssize_t)sizeof(t) ? 0 : 2);
}

int share_many(const char *dev, unsigned int procs, unsigned int commands,
	       struct share_tally *sum)
{
	struct share_tally t;
	unsigned int c;
	int fds[2], st, r = 0;

	memset(sum, 0, sizeof(*sum));
	if (pipe(fds) < 0) {
		snprintf(sum->msg, sizeof(sum->msg), "pipe: %s", strerror(errno));
		return -1;
	}
	for (c = 0; c < procs; c++) {
		pid_t p = fork();

		if (p == 0) {
			close(fds[0]);
			worker(dev, c, commands, fds[1]);
		}
		if (p < 0)
			r = -1;
	}
	close(fds[1]);
	for (c = 0; c < procs; c++) {
		if (read(fds[0], &t, sizeof(t)) != (ssize_t)sizeof(t)) {
			r = -1;
			snprintf(sum->msg, sizeof(sum->msg),
				 "a process did not report");
			break;
		}
		if (t.errors && !sum->errors)
			snprintf(sum->msg, sizeof(sum->msg), "%s", t.msg);
		sum->done += t.done;
		sum->wrong += t.wrong;
		sum->errors += t.errors;
		if (t.max_ms > sum->max_ms)
			sum->max_ms = t.max_ms;
	}
	close(fds[0]);
	while (wait(&st) > 0)
		if (!WIFEXITED(st) || WEXITSTATUS(st) != 0)
			r = -1;
	return r;
}

int share_lock_path(const char *dev, char *buf, size_t len)
{
	const char *dir = getenv("SH2000_LOCK_DIR");
	struct stat sb;

	if (!dir || !*dir)
		dir = access("/run/lock", W_OK) == 0 ? "/run/lock" : "/tmp";
	if (!strncmp(dev, "sim:", 4))
		return snprintf(buf, len, "%s/sh2000-shm-%s.lock", dir, dev + 4);
	if (stat(dev, &sb) < 0 || !S_ISCHR(sb.st_mode))
		return -1;
	return snprintf(buf, len, "%s/sh2000-dev-%u-%u.lock", dir,
			major(sb.st_rdev), minor(sb.st_rdev));
}

int share_cmd_lock_held(const char *path)
{
	struct flock fl = { .l_type = F_WRLCK, .l_whence = SEEK_SET,
			    .l_start = 0, .l_len = 1 };
	int fd = open(path, O_RDWR), r;

	if (fd < 0)
		return 0;
	r = fcntl(fd, F_OFD_GETLK, &fl) == 0 && fl.l_type != F_UNLCK;
	close(fd);
	return r;
}

/* A process sending nop after nop until it is killed. */
static pid_t spawn_nopper(const char *dev)
{
	pid_t p = fork();

	if (p == 0) {
		char msg[200];
		struct sh2000 *c = share_open(dev, msg, sizeof(msg));

		for (;;)
			if (!c || sh2000_nop(c) < 0)
				pause();
	}
	return p;
}

int share_killed_in_command(const char *dev, unsigned int rounds,
			    unsigned int *held, double *worst_ms, char *msg,
			    size_t len)
{
	char path[512];
	struct sh2000 *h;
	unsigned int k, waits;
	double t0, ms;
	int st, r;
	pid_t p;

	*held = 0;
	*worst_ms = 0;
	if (share_lock_path(dev, path, sizeof(path)) < 0) {
		snprintf(msg, len, "%s: no lock file name", dev);
		return -1;
	}
	for (k = 0; k < rounds; k++) {
		p = spawn_nopper(dev);
		if (p < 0) {
			snprintf(msg, len, "fork: %s", strerror(errno));
			return -1;
		}
		/* stopped inside a command (the lock held while it stands
		 * still), else let go on and caught again: a check and a
		 * kill apart let a short command end between them (0 of 8
		 * in the kernel suite's VM once) */
		for (waits = 0; waits < 100000; waits++) {
			if (!share_cmd_lock_held(path)) {
				usleep(100);
				continue;
			}
			kill(p, SIGSTOP);
			waitpid(p, &st, WUNTRACED);
			if (share_cmd_lock_held(path)) {
				*held += 1;
				break;
			}
			kill(p, SIGCONT);
		}
		kill(p, SIGKILL);
		waitpid(p, &st, 0);
		h = share_open(dev, msg, len);
		if (!h)
			return -1;
		t0 = share_now_ms();
		r = sh2000_nop(h);
		if (!r)
			r = sh2000_param_set(h, 1, SH2000_P_TD, 0.25);
		ms = share_now_ms() - t0;
		if (r < 0) {
			snprintf(msg, len, "after a SIGKILL in a command: %s",
				 sh2000_last_error(h));
			sh2000_close(h);
			return r;
		}
		sh2000_close(h);
		if (ms > *worst_ms)
			*worst_ms = ms;
	}
	return 0;
}

int share_spawn_holder(const char *dev, int *claimed)
{
	int fds[2];
	char ok = 0;
	pid_t p;

	*claimed = 0;
	if (pipe(fds) < 0)
		return -1;
	p = fork();
	if (p == 0) {
		char msg[200];
		struct sh2000 *h = share_open(dev, msg, sizeof(msg));

		ok = h && sh2000_claim_motion(h) == 0;
		if (write(fds[1], &ok, 1) != 1)
			_exit(2);
		for (;;)
			pause();
	}
	if (p > 0 && read(fds[0], &ok, 1) == 1)
		*claimed = ok;
	close(fds[0]);
	close(fds[1]);
	return p;
}
