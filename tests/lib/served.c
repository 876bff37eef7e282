/* SPDX-License-Identifier: MIT */
/* Helpers of the real-time fault matrices: see served.h. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "served.h"
#include "sh2000/run.h"

const char *const served_act_name[ACTS] = { "idle", "run", "per-period" };

double served_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void served_name(char *buf, size_t len, const char *what)
{
	snprintf(buf, len, "sim:mx-%s-%d", what, (int)getpid());
}

void served_card_wait(struct sh2000_sim_server *s, double ms)
{
	const struct timespec tick = { 0, 1000000 };
	struct sh2000_probe p;
	double t0 = served_now_ms();
	uint64_t from, card_ns = (uint64_t)(ms * 1e6);

	sh2000_sim_server_probe(s, &p);
	from = p.time_ns;
	while (p.time_ns - from < card_ns) {
		if (served_now_ms() - t0 > 20.0 * ms)
			fail_msg("the served card's clock ran %.1f ms of the %.1f ms waited for in %.0f ms",
				 (double)(p.time_ns - from) * 1e-6, ms,
				 served_now_ms() - t0);
		nanosleep(&tick, NULL);
		sh2000_sim_server_probe(s, &p);
	}
}

/* A server just started may not have run its first cycle within the
 * heartbeat limit on a loaded machine: that is tried again (1 s). */
struct sh2000 *served_open(const char *dev)
{
	const struct timespec pause_50ms = { 0, 50000000 };
	struct sh2000 *h = NULL;
	char msg[256];
	int r, tries = 0;

	while ((r = sh2000_open(&h, dev, msg, sizeof(msg))) ==
	       -SH2000_EHEARTBEAT && ++tries < 20)
		nanosleep(&pause_50ms, NULL);
	if (r < 0)
		fail_msg("open %s: %s", dev, msg);
	return h;
}

/* ---- a card served by a child process -------------------------------- */

struct inject_req {
	int quit;
	enum sh2000_inject what;
	unsigned int axis, arg;
};

/* The child: serve in the server's thread, inject what the parent asks,
 * answer each request with one byte. The end of the requests (the
 * parent gone) stops it as a quit does. */
static void __attribute__((noreturn))
serve_child(const char *dev, int req_fd, int ack_fd)
{
	struct sh2000_sim_server *s = NULL;
	struct inject_req q;
	char msg[256];

	/* a test that fails must not leave its card running */
	prctl(PR_SET_PDEATHSIG, SIGKILL);
	if (sh2000_sim_server_create(&s, dev + 4, NULL, 0, msg, sizeof(msg)) ||
	    rt_server_start(s)) {
		fprintf(stderr, "server %s: %s\n", dev, msg);
		_exit(3);
	}
	(void)!write(ack_fd, "r", 1);
	while (read(req_fd, &q, sizeof(q)) == (ssize_t)sizeof(q) && !q.quit) {
		int r = sh2000_sim_server_inject(s, q.what, q.axis, q.arg);

		(void)!write(ack_fd, r < 0 ? "e" : "k", 1);
	}
	sh2000_sim_server_destroy(s);
	_exit(0);
}

void served_spawn(struct served_card *c, const char *dev)
{
	int req[2], ack[2];
	char ch;

	if (pipe(req) || pipe(ack))
		fail_msg("pipe");
	c->pid = fork();
	if (c->pid < 0)
		fail_msg("fork");
	if (c->pid == 0) {
		close(req[1]);
		close(ack[0]);
		serve_child(dev, req[0], ack[1]);
	}
	close(req[0]);
	close(ack[1]);
	c->cmd = req[1];
	c->ack = ack[0];
	if (read(c->ack, &ch, 1) != 1)
		fail_msg("server did not start on %s", dev);
}

void served_inject(struct served_card *c, enum sh2000_inject what,
		   unsigned int axis, unsigned int arg)
{
	struct inject_req q = { 0, what, axis, arg };
	char ch = 0;

	if (write(c->cmd, &q, sizeof(q)) != (ssize_t)sizeof(q) ||
	    read(c->ack, &ch, 1) != 1 || ch != 'k')
		fail_msg("inject %d on the served card failed", (int)what);
}

static void reap(struct served_card *c)
{
	int st;

	waitpid(c->pid, &st, 0);
	close(c->cmd);
	close(c->ack);
	c->pid = 0;
}

void served_end(struct served_card *c)
{
	struct inject_req q = { .quit = 1 };

	(void)!write(c->cmd, &q, sizeof(q));
	reap(c);
}

void served_kill(struct served_card *c)
{
	kill(c->pid, SIGKILL);
	reap(c);
}

unsigned int served_fault_arg(struct sh2000 *h, enum sh2000_inject what)
{
	uint16_t head = 0;

	if (what == SH2000_INJECT_LIMIT)
		return 1;
	if (what != SH2000_INJECT_RAM_FLIP)
		return 0;
	CHECK(sh2000_ram_read(h, SH2000_W_HEAD, 1, &head));
	return simtest_last_record_word(head);
}

/* ---- the host's activities --------------------------------------------- */

static void at_point(void *arg)
{
	struct served_act *c = arg;

	if (c->done)
		return;
	c->done = 1;
	c->t_fault = served_now_ms();
	if (c->victim > 0)
		kill(c->victim, SIGKILL);
	if (c->at)
		c->at(c->arg);
	if (c->signal_fd >= 0)
		(void)!write(c->signal_fd, "x", 1);
}

static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	if (p->points >= SERVED_AT_POINT)
		at_point(ctx);
}

static int act_run(struct sh2000 *h, struct served_act *c)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run *r;
	const double b[4] = { 400.0, 0, 0, 0 };
	char msg[256];
	int e;

	CHECK(sh2000_run_path_config(h, &pc));
	sh2000_run_config_default(&rc);
	rc.progress = on_progress;
	rc.ctx = c;
	if (sh2000_run_create(&r, h, &pc, &rc, msg, sizeof(msg)) < 0)
		fail_msg("run_create: %s", msg);
	e = sh2000_path_line(sh2000_run_path(r), b, SERVED_FEED);
	if (!e)
		e = sh2000_run_finish(r);
	sh2000_run_destroy(r);
	return e;
}

static int act_idle(struct sh2000 *h, struct served_act *c)
{
	int e;

	at_point(c);
	while (!(e = sh2000_poll(h, NULL)))
		if (c->victim <= 0 && !c->at)
			pause();	/* until killed */
		else
			sh2000_sleep_ns(h, 1000000ull);
	return e;
}

int served_activity(struct sh2000 *h, enum served_activity a,
		    struct served_act *c)
{
	const struct simtest_period pc = {
		.feed = SERVED_FEED, .ahead = 4, .at_point = SERVED_AT_POINT,
		.max_points = 100000, .at = at_point, .ctx = c,
	};

	CHECK(sh2000_enable(h, 0xf));
	return a == ACT_IDLE ? act_idle(h, c) :
	       a == ACT_RUN ? act_run(h, c) : simtest_period(h, &pc);
}
