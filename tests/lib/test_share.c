/* SPDX-License-Identifier: MIT */
/*
 * Several programs on one card (sim:NAME, a served card model): every
 * command answer goes to the process that asked, the motion belongs to one
 * program at a time and its holder is named, and a process killed while it
 * holds a lock does not wedge the card.
 *
 * SHARE_PROCS processes x SHARE_COMMANDS mixed commands: set and get of a
 * parameter no other process touches (the value read must be the value
 * this process set, float32-rounded), nop, enable/disable of an axis no
 * other process touches. 0 wrong values, 0 errors.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "simtest.h"

#define SHARE_PROCS	8
#define SHARE_COMMANDS	10000
/* After a SIGKILL of a lock holder, the next command of another process
 * is answered within this (docs/library.md). */
#define SHARE_RECOVER_MS	50

struct tally {
	unsigned int done, wrong, errors;
	double max_ms;		/* slowest command, waiting included */
	int first_error;
	char msg[200];
};

static char dev[96];

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static struct sh2000 *open_dev(void)
{
	struct sh2000 *h = NULL;
	char msg[256];

	if (sh2000_open(&h, dev, msg, sizeof(msg)) < 0)
		fail_msg("%s", msg);
	/* real time on a loaded 2-core machine */
	sh2000_set_heartbeat_limit(h, 2000000000ull);
	return h;
}

static void note_error(struct tally *t, struct sh2000 *h, int r)
{
	if (!t->errors++) {
		t->first_error = r;
		snprintf(t->msg, sizeof(t->msg), "%s", sh2000_last_error(h));
	}
}

/* One worker: axis c % 4; parameter kp for c < 4, td else. */
static void worker(unsigned int c, int out)
{
	struct sh2000 *h = open_dev();
	unsigned int axis = c % SH2000_AXES, i;
	unsigned int param = c < SH2000_AXES ? SH2000_P_KP : SH2000_P_TD;
	struct tally t = { 0 };
	double set = 0.0, v;
	int r;

	srand(c + 1);
	for (i = 0; i < SHARE_COMMANDS; i++) {
		double t0 = now_ms();

		switch (i % 4) {
		case 0:
			v = (double)(float)(0.001 * (rand() % 1000 + 1) +
					    c * 1e-6);
			r = sh2000_param_set(h, (int)axis, param, v);
			if (!r)
				set = v;
			break;
		case 1:
			r = sh2000_param_get(h, (int)axis, param, &v);
			if (!r && v != set)
				t.wrong++;
			break;
		case 2:
			r = sh2000_nop(h);
			break;
		default:
			if (c >= SH2000_AXES)
				r = sh2000_nop(h);
			else if ((i / 4) % 2)
				r = sh2000_disable(h, 1u << axis);
			else
				r = sh2000_enable(h, 1u << axis);
			break;
		}
		if (r < 0)
			note_error(&t, h, r);
		if (now_ms() - t0 > t.max_ms)
			t.max_ms = now_ms() - t0;
		t.done++;
	}
	sh2000_close(h);
	if (write(out, &t, sizeof(t)) != (ssize_t)sizeof(t))
		_exit(2);
	_exit(0);
}

static struct sh2000_sim_server *serve(void)
{
	static unsigned int serial;
	struct sh2000_sim_server *s = NULL;
	char n[64], msg[256];

	snprintf(n, sizeof(n), "test-share-%d-%u", (int)getpid(), serial++);
	snprintf(dev, sizeof(dev), "sim:%s", n);
	if (sh2000_sim_server_create(&s, n, NULL, 0, msg, sizeof(msg)) < 0)
		fail_msg("server: %s", msg);
	assert_int_equal(sh2000_sim_server_start(s), 0);
	return s;
}

static void test_many_processes(void **state)
{
	struct sh2000_sim_server *s = serve();
	struct tally t, sum = { 0 };
	int fds[2], st;
	unsigned int c;
	double t0 = now_ms();

	(void)state;
	assert_int_equal(pipe(fds), 0);
	for (c = 0; c < SHARE_PROCS; c++) {
		pid_t p = fork();

		assert_true(p >= 0);
		if (p == 0) {
			close(fds[0]);
			worker(c, fds[1]);
		}
	}
	close(fds[1]);
	for (c = 0; c < SHARE_PROCS; c++) {
		assert_int_equal(read(fds[0], &t, sizeof(t)), (ssize_t)sizeof(t));
		if (t.errors && !sum.errors)
			snprintf(sum.msg, sizeof(sum.msg), "%s", t.msg);
		sum.done += t.done;
		sum.wrong += t.wrong;
		sum.errors += t.errors;
		if (t.max_ms > sum.max_ms)
			sum.max_ms = t.max_ms;
	}
	close(fds[0]);
	while (wait(&st) > 0)
		assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	printf("%u processes x %u commands: %u done in %.1f s (slowest %.1f ms), %u wrong values, %u errors%s%s\n",
	       SHARE_PROCS, SHARE_COMMANDS, sum.done, (now_ms() - t0) / 1e3,
	       sum.max_ms, sum.wrong, sum.errors, sum.errors ? ": " : "",
	       sum.msg);
	assert_int_equal(sum.done, SHARE_PROCS * SHARE_COMMANDS);
	assert_int_equal(sum.wrong, 0);
	assert_int_equal(sum.errors, 0);
	sh2000_sim_server_destroy(s);
}

/* A child that holds the motion, then waits to be killed. */
static pid_t holder_child(int ready)
{
	pid_t p = fork();

	assert_true(p >= 0);
	if (p == 0) {
		struct sh2000 *h = open_dev();
		char ok = sh2000_claim_motion(h) == 0;

		if (write(ready, &ok, 1) != 1)
			_exit(2);
		for (;;)
			pause();
	}
	return p;
}

static void test_motion_owner(void **state)
{
	struct sh2000_sim_server *s = serve();
	struct sh2000 *h;
	char ok = 0, who[128], pidstr[32];
	int fds[2], st;
	double t0;
	pid_t p;

	(void)state;
	assert_int_equal(pipe(fds), 0);
	p = holder_child(fds[1]);
	assert_int_equal(read(fds[0], &ok, 1), 1);
	assert_true(ok);
	h = open_dev();
	/* the others are told who holds it, and may not enable... */
	assert_int_equal(sh2000_motion_holder(h, who, sizeof(who)), 1);
	snprintf(pidstr, sizeof(pidstr), "pid %d", (int)p);
	assert_non_null(strstr(who, pidstr));
	assert_int_equal(sh2000_enable(h, 1), -SH2000_EOWNED);
	assert_non_null(strstr(sh2000_last_error(h), pidstr));
	assert_int_equal(sh2000_claim_motion(h), -SH2000_EOWNED);
	/* ... but look, set parameters and stop */
	CHECK(sh2000_nop(h));
	CHECK(sh2000_param_set(h, 0, SH2000_P_KP, 0.5));
	CHECK(sh2000_stop(h));
	/* the holder dies: the motion is free at once */
	kill(p, SIGKILL);
	waitpid(p, &st, 0);
	t0 = now_ms();
	CHECK(sh2000_claim_motion(h));
	CHECK(sh2000_enable(h, 1));
	printf("motion claimed %.2f ms after the holder was killed\n",
	       now_ms() - t0);
	assert_true(now_ms() - t0 < SHARE_RECOVER_MS);
	assert_int_equal(sh2000_motion_holder(h, who, sizeof(who)), 1);
	sh2000_release_motion(h);
	assert_int_equal(sh2000_motion_holder(h, who, sizeof(who)), 0);
	sh2000_close(h);
	close(fds[0]);
	close(fds[1]);
	sh2000_sim_server_destroy(s);
}

/* Is the command lock (byte 0 of the lock file) held by anyone? */
static int cmd_lock_held(const char *path)
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

static void test_killed_in_command(void **state)
{
	struct sh2000_sim_server *s = serve();
	char path[512];
	const char *dir = getenv("SH2000_LOCK_DIR");
	struct sh2000 *h;
	unsigned int tries;
	double t0;
	int st, held = 0;
	pid_t p;

	(void)state;
	snprintf(path, sizeof(path), "%s/sh2000-shm-%s.lock", dir, dev + 4);
	/* kill a process that sends commands back to back while it holds
	 * the command lock; a few rounds, the lock is taken most of the
	 * time */
	for (tries = 0; tries < 20 && held < 5; tries++) {
		p = fork();
		assert_true(p >= 0);
		if (p == 0) {
			struct sh2000 *c = open_dev();

			for (;;)
				(void)sh2000_nop(c);
		}
		while (!cmd_lock_held(path))
			usleep(100);
		held += cmd_lock_held(path);
		kill(p, SIGKILL);
		waitpid(p, &st, 0);
		h = open_dev();
		t0 = now_ms();
		CHECK(sh2000_nop(h));
		CHECK(sh2000_param_set(h, 1, SH2000_P_TD, 0.25));
		printf("killed in a command: next answered after %.2f ms\n",
		       now_ms() - t0);
		assert_true(now_ms() - t0 < SHARE_RECOVER_MS);
		sh2000_close(h);
	}
	assert_true(held > 0);
	sh2000_sim_server_destroy(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_many_processes),
		cmocka_unit_test(test_motion_owner),
		cmocka_unit_test(test_killed_in_command),
	};
	char tmpl[] = "/tmp/sh2000-locks-XXXXXX";

	/* the test's own lock files, removed with the folder */
	if (!mkdtemp(tmpl))
		return 1;
	setenv("SH2000_LOCK_DIR", tmpl, 1);
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	char cmd[128];

	snprintf(cmd, sizeof(cmd), "rm -rf %s", tmpl);
	if (system(cmd) != 0)
		return 1;
	return r;
}
