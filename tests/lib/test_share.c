/* SPDX-License-Identifier: MIT */
/*
 * Several programs on one card (sim:NAME, a served card model): every
 * command answer goes to the process that asked, the motion belongs to one
 * program at a time and its holder is named, and a process killed while it
 * holds a lock does not wedge the card.
 *
 * SHARE_PROCS processes x SHARE_COMMANDS mixed commands (share.h says
 * which): 0 wrong values, 0 errors. The checks are in share.c, which the
 * VM suite also runs on /dev/sh2000-0 (sh2000-share).
 */
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rt.h"
#include "share.h"
#include "simtest.h"

#define SHARE_PROCS	8
#define SHARE_COMMANDS	10000
/* After a SIGKILL of a lock holder, the next command of another process
 * is answered within this (docs/library.md). */
#define SHARE_RECOVER_MS	50

static char dev[96];

static struct sh2000 *open_dev(void)
{
	char msg[256];
	struct sh2000 *h = share_open(dev, msg, sizeof(msg));

	if (!h)
		fail_msg("%s", msg);
	return h;
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
	assert_int_equal(rt_server_start(s), 0);
	return s;
}

static void test_many_processes(void **state)
{
	struct sh2000_sim_server *s = serve();
	struct share_tally sum;
	double t0 = share_now_ms();
	int r;

	(void)state;
	r = share_many(dev, SHARE_PROCS, SHARE_COMMANDS, &sum);
	printf("%u processes x %u commands: %u done in %.1f s (slowest %.1f ms), %u wrong values, %u errors%s%s\n",
	       SHARE_PROCS, SHARE_COMMANDS, sum.done,
	       (share_now_ms() - t0) / 1e3, sum.max_ms, sum.wrong, sum.errors,
	       sum.errors || r ? ": " : "", sum.msg);
	assert_int_equal(r, 0);
	assert_int_equal(sum.done, SHARE_PROCS * SHARE_COMMANDS);
	assert_int_equal(sum.wrong, 0);
	assert_int_equal(sum.errors, 0);
	sh2000_sim_server_destroy(s);
}

static void test_motion_owner(void **state)
{
	struct sh2000_sim_server *s = serve();
	struct sh2000 *h;
	char who[128], pidstr[32];
	int claimed, st;
	double t0;
	pid_t p;

	(void)state;
	p = share_spawn_holder(dev, &claimed);
	assert_true(p > 0);
	assert_true(claimed);
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
	t0 = share_now_ms();
	CHECK(sh2000_claim_motion(h));
	CHECK(sh2000_enable(h, 1));
	printf("motion claimed %.2f ms after the holder was killed\n",
	       share_now_ms() - t0);
	assert_true(share_now_ms() - t0 < SHARE_RECOVER_MS);
	assert_int_equal(sh2000_motion_holder(h, who, sizeof(who)), 1);
	sh2000_release_motion(h);
	assert_int_equal(sh2000_motion_holder(h, who, sizeof(who)), 0);
	sh2000_close(h);
	sh2000_sim_server_destroy(s);
}

static void test_killed_in_command(void **state)
{
	struct sh2000_sim_server *s = serve();
	unsigned int held;
	double worst;
	char msg[256];

	(void)state;
	/* kill a process that sends commands back to back while it holds
	 * the command lock; a few rounds, the lock is taken most of the
	 * time */
	if (share_killed_in_command(dev, 8, &held, &worst, msg,
				    sizeof(msg)) < 0)
		fail_msg("%s", msg);
	printf("killed in a command (%u of 8 times holding the lock): next answered after at most %.2f ms\n",
	       held, worst);
	assert_true(held > 0);
	assert_true(worst < SHARE_RECOVER_MS);
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

	/* the times this process measures are a real-time client's; the
	 * processes it forks are ordinary programs */
	rt_fifo(RT_HOST, RT_RESET_ON_FORK);
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
