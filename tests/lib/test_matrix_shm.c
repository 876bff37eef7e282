/* SPDX-License-Identifier: MIT */
/*
 * The fault matrix's process faults (docs/faults.md), on a served card
 * (sim:NAME) in real time: the host killed with SIGKILL, and the server
 * (the card) killed, each while the host is idle, streams a run, or
 * streams one record per period. Host killed: another client watching the
 * card sees it stop and the right fault latched within the documented
 * time (the card's host timeout, or an underrun when little was queued),
 * the motion lock is free at once, a reset brings the card back and the
 * next run works. Server killed: the host learns within the heartbeat
 * limit of sim:NAME; a new server takes the name and the next run works.
 */
#include <signal.h>
#include <stdlib.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "served.h"

#define POLL_NS		1000000ull

struct cell {
	int ran;
	int code;		/* the error a client learnt */
	unsigned int faults;	/* latched */
	double detect_ms, rest_ms;
};

static struct cell killed_host[ACTS], killed_server[ACTS];
static struct cell killed_host_quiet;	/* a run, nobody else polling */


/* ---- host killed ------------------------------------------------------ */

/* Watch the card from another client after the kill: when a fault shows
 * and when the set-points have stood still for 5 polls. */
static void watch_after_kill(struct sh2000 *h, double t0, struct cell *c)
{
	struct sh2000_status st;
	int32_t last = 0;
	unsigned int still = 0;
	double t_still = -1.0, t;

	c->detect_ms = -1.0;
	while ((t = served_now_ms() - t0) < 1000.0) {
		CHECK(sh2000_poll(h, &st));
		if (c->detect_ms < 0 && st.card_faults) {
			c->detect_ms = t;
			c->faults = st.card_faults;
			c->code = sh2000_status_error(h, &st);
		}
		if (st.axis[0].cmd_counts == last &&
		    st.card_state != SH2000_STATE_RUNNING) {
			if (!still++)
				t_still = t;
		} else {
			still = 0;
		}
		last = st.axis[0].cmd_counts;
		if (still >= 5 && (c->detect_ms >= 0 || t > 300.0))
			break;
		CHECK(sh2000_sleep_ns(h, POLL_NS));
	}
	c->rest_ms = t_still;
}

/* The same without a poll (no host heartbeat from the watcher): the
 * server's probe, between two cycles. The faults are read at the end. */
static void watch_quietly(struct sh2000_sim_server *s, struct sh2000 *h,
			  double t0, struct cell *c)
{
	const struct timespec ms = { 0, 1000000 };
	struct sh2000_status st;
	struct sh2000_probe p;
	double last = 0.0, t;
	unsigned int still = 0;

	c->detect_ms = -1.0;
	c->rest_ms = -1.0;
	while ((t = served_now_ms() - t0) < 1000.0) {
		sh2000_sim_server_probe(s, &p);
		if (c->detect_ms < 0 && p.state != SH2000_STATE_RUNNING)
			c->detect_ms = t;
		if (p.axis[0].fine_cmd == last &&
		    p.state != SH2000_STATE_RUNNING) {
			if (!still++)
				c->rest_ms = t;
		} else {
			still = 0;
		}
		last = p.axis[0].fine_cmd;
		if (still >= 5)
			break;
		nanosleep(&ms, NULL);
	}
	CHECK(sh2000_poll(h, &st));
	c->faults = st.card_faults;
	c->code = sh2000_status_error(h, &st);
}

/* 1, or 0 when the host ended before the fault (tried again). */
static int host_killed_once(enum served_activity a, int quiet)
{
	struct sh2000_sim_server *s = NULL;
	struct cell *c = quiet ? &killed_host_quiet : &killed_host[a];
	char dev[80], msg[256], ch;
	int go[2], ready[2], st;
	struct sh2000 *h;
	pid_t pid;
	double t0;

	served_name(dev, sizeof(dev), "host");
	if (pipe(go) || pipe(ready))
		fail_msg("pipe");
	pid = fork();
	if (pid == 0) {
		struct served_act ctx = { .signal_fd = ready[1] };

		prctl(PR_SET_PDEATHSIG, SIGKILL);
		close(go[1]);
		(void)!read(go[0], &ch, 1);
		h = served_open(dev);
		served_activity(h, a, &ctx);
		_exit(1);	/* the activity ended before the kill */
	}
	close(go[0]);
	close(ready[1]);
	if (sh2000_sim_server_create(&s, dev + 4, NULL, 0, msg, sizeof(msg)))
		fail_msg("server: %s", msg);
	CHECK(rt_server_start(s));
	h = served_open(dev);
	(void)!write(go[1], "x", 1);
	if (read(ready[0], &ch, 1) != 1) {
		/* underrun before the fault: see server_killed() */
		fprintf(stderr, "%s: the host ended before the fault\n",
			served_act_name[a]);
		waitpid(pid, &st, 0);
		sh2000_close(h);
		sh2000_sim_server_destroy(s);
		close(go[1]);
		close(ready[0]);
		return 0;
	}
	kill(pid, SIGKILL);
	t0 = served_now_ms();
	waitpid(pid, &st, 0);
	if (quiet)
		watch_quietly(s, h, t0, c);
	else
		watch_after_kill(h, t0, c);
	c->ran = 1;
	/* the dead host's motion lock is free at once */
	CHECK(sh2000_claim_motion(h));
	simtest_next_run(h);
	sh2000_close(h);
	sh2000_sim_server_destroy(s);
	close(go[1]);
	close(ready[0]);
	return 1;
}

static void host_killed(enum served_activity a, int quiet)
{
	int tries = 0;

	while (!host_killed_once(a, quiet))
		if (++tries == 3)
			fail_msg("%s: the host ended before the fault %d times",
				 served_act_name[a], tries);
}

static void test_host_killed(void **state)
{
	unsigned int a;

	(void)state;
	for (a = 0; a < ACTS; a++)
		host_killed(a, 0);
	host_killed(ACT_RUN, 1);
	/* idle: nothing moves, nothing latches */
	assert_int_equal(killed_host[ACT_IDLE].faults, 0);
	/*
	 * A run keeps 64 records (128 ms) queued. The watching client's
	 * polls count as host heartbeats (protocol.md 6: any poll), so the
	 * card's host timeout does not fire while another program polls:
	 * the card runs its ring out and stops on the underrun, a controlled
	 * stop (21 ms at 100 mm/s).
	 */
	assert_int_equal(killed_host[ACT_RUN].code, -SH2000_EUNDERRUN);
	assert_true(killed_host[ACT_RUN].detect_ms <= 128.0 + SERVED_SLACK_MS);
	assert_true(killed_host[ACT_RUN].rest_ms <= 128.0 + 21.0 + SERVED_SLACK_MS);
	/* nobody else polls: the card's host timeout (HOST_TIMEOUT_MS) ends
	 * the motion with a controlled stop */
	assert_int_equal(killed_host_quiet.code, -SH2000_EHOST_TIMEOUT);
	assert_true(killed_host_quiet.detect_ms >= 100.0 - 5.0);
	assert_true(killed_host_quiet.detect_ms <= 100.0 + SERVED_SLACK_MS);
	assert_true(killed_host_quiet.rest_ms <= 100.0 + 21.0 + SERVED_SLACK_MS);
	/* 4 records queued (8 ms): the ring runs dry first */
	assert_int_equal(killed_host[ACT_PERIOD].code, -SH2000_EUNDERRUN);
	assert_true(killed_host[ACT_PERIOD].detect_ms <= 8.0 + SERVED_SLACK_MS);
	assert_true(killed_host[ACT_PERIOD].rest_ms <= 8.0 + 21.0 + SERVED_SLACK_MS);
}

/* ---- server killed ---------------------------------------------------- */

/* The server killed during activity a on dev: 1 when the activity was
 * under way at the fault, 0 when the host failed before it (then the
 * cell says nothing and is tried again). */
static int server_killed_once(enum served_activity a, const char *dev)
{
	struct cell *c = &killed_server[a];
	struct served_act ctx = { .signal_fd = -1 };
	struct served_card card;
	struct sh2000 *h;

	served_spawn(&card, dev);
	ctx.victim = card.pid;
	h = served_open(dev);
	c->code = served_activity(h, a, &ctx);
	c->detect_ms = served_now_ms() - ctx.t_fault;
	c->ran = 1;
	served_kill(&card);	/* reaped; killed too if the host failed before */
	if (!ctx.done)
		fprintf(stderr, "%s: the host failed before the fault: %s\n",
			served_act_name[a], sh2000_last_error(h));
	sh2000_close(h);
	return ctx.done;
}

/*
 * A one-record-per-period stream keeps 4 records (8 ms) queued, like
 * LinuxCNC; a host descheduled longer than that (one without the
 * privilege for SCHED_FIFO, rt.h, on a busy machine) underruns before the
 * fault is injected. That is not the cell's outcome, so such a start is
 * tried again, three times at most.
 */
static void server_killed(enum served_activity a)
{
	struct served_card card;
	struct sh2000 *h;
	int tries = 0;
	char dev[80];

	served_name(dev, sizeof(dev), "server");
	while (!server_killed_once(a, dev))
		if (++tries == 3)
			fail_msg("%s: the host failed before the fault %d times",
				 served_act_name[a], tries);
	/* a new server takes the name the dead one left */
	served_spawn(&card, dev);
	h = served_open(dev);
	simtest_next_run(h);
	sh2000_close(h);
	served_end(&card);
}

static void test_server_killed(void **state)
{
	unsigned int a;

	(void)state;
	for (a = 0; a < ACTS; a++) {
		server_killed(a);
		/* the heartbeat limit of sim:NAME, plus a poll */
		assert_int_equal(killed_server[a].code, -SH2000_EHEARTBEAT);
		assert_true(killed_server[a].detect_ms <=
			    SH2000_HEARTBEAT_LIMIT_SHM_NS * 1e-6 + 5.0 + SERVED_SLACK_MS);
	}
}

static void print_table(void)
{
	unsigned int a;

	printf("| fault | host | a client learns | in ms | card at rest after ms | faults latched |\n");
	printf("| --- | --- | --- | ---: | ---: | --- |\n");
	for (a = 0; a < ACTS; a++) {
		char ms[32] = "-";

		if (!killed_host[a].ran)
			continue;
		if (killed_host[a].code)
			snprintf(ms, sizeof(ms), "%.1f", killed_host[a].detect_ms);
		printf("| host SIGKILL | %s | %s | %s | %.1f | 0x%04x |\n",
		       served_act_name[a], killed_host[a].code ?
		       sh2000_strerror(killed_host[a].code) : "nothing", ms,
		       killed_host[a].rest_ms, killed_host[a].faults);
	}
	if (killed_host_quiet.ran)
		printf("| host SIGKILL | run, no other client | %s | %.1f | %.1f | 0x%04x |\n",
		       sh2000_strerror(killed_host_quiet.code),
		       killed_host_quiet.detect_ms, killed_host_quiet.rest_ms,
		       killed_host_quiet.faults);
	for (a = 0; a < ACTS; a++)
		if (killed_server[a].ran)
			printf("| server SIGKILL | %s | %s | %.1f | - | - |\n",
			       served_act_name[a], sh2000_strerror(killed_server[a].code),
			       killed_server[a].detect_ms);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_host_killed),
		cmocka_unit_test(test_server_killed),
	};
	int r;

	/* the hosts whose times the matrix judges, real-time ones (the
	 * processes and tools it starts inherit it), below the card */
	rt_fifo(RT_HOST, 0);
	r = cmocka_run_group_tests(tests, NULL, NULL);

	print_table();
	return r;
}
