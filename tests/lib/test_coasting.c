/* SPDX-License-Identifier: MIT */
/*
 * A carriage the card let go of coasts (the promise: after any fault "reset
 * brings the card back, and the next run works"). A DSP stall while X
 * moves at 100 mm/s leaves X disabled (the counter jumped by the distance
 * the carriage went meanwhile) and its carriage coasting on its friction
 * for about 1.4 s. Right after the reset a run on Y alone must work while
 * X still coasts: the records hold X where the host read it, and the card
 * must not compare them with the coasting encoder (docs/protocol.md 7.4,
 * REJECT_DISABLED). A run whose records do move a disabled axis is still
 * rejected, and the runner's message names the axis. In-process card
 * (`sim`), virtual time.
 */
#include <stdlib.h>

#include "simtest.h"

#define FEED		100.0	/* mm/s along X before the fault */
#define AT_POINT	150u	/* records streamed before the stall */
#define FERR_MM		0.2	/* the default FERR_LIMIT, 20000 counts */

/*
 * A line from where the card is, by[a] mm along each axis a at feed mm/s,
 * through the runner with rc's callbacks (NULL: none). Its result; its
 * error in err; the start in start.
 */
static int run_line(struct sh2000 *h, const struct sh2000_run_config *rc,
		    const double by[SH2000_AXES], double feed,
		    double start[SH2000_AXES], char *err, size_t len)
{
	struct sh2000_path_config pc;
	struct sh2000_run *r;
	double end[SH2000_AXES];
	char msg[256];
	unsigned int a;
	int e;

	CHECK(sh2000_run_path_config(h, &pc));
	if (sh2000_run_create(&r, h, &pc, rc, msg, sizeof(msg)) < 0)
		fail_msg("run_create: %s", msg);
	for (a = 0; a < SH2000_AXES; a++)
		end[a] = pc.start[a] + by[a];
	memcpy(start, pc.start, sizeof(pc.start));
	e = sh2000_path_line(sh2000_run_path(r), end, feed);
	if (!e)
		e = sh2000_run_finish(r);
	snprintf(err, len, "%s", e ? sh2000_run_error(r) : "");
	sh2000_run_destroy(r);
	return e;
}

struct stall {
	struct sh2000 *h;
	int injected;
};

static void stall_at(void *ctx, const struct sh2000_run_progress *p)
{
	struct stall *s = ctx;
	struct sh2000 *h = s->h;

	if (s->injected || p->points < AT_POINT)
		return;
	s->injected = 1;
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_DSP_STALL, 0, 0));
}

/* X at 100 mm/s, a DSP stall after AT_POINT records: the runner learns
 * the stopped heartbeat and stops the card with an emergency stop. */
static void stall_while_x_moves(struct sh2000 *h)
{
	const double by[SH2000_AXES] = { 200.0, 0, 0, 0 };
	struct stall s = { .h = h };
	struct sh2000_run_config rc;
	double start[SH2000_AXES];
	char err[512];
	int e;

	CHECK(sh2000_enable(h, 0x1));
	sh2000_run_config_default(&rc);
	rc.progress = stall_at;
	rc.ctx = &s;
	e = run_line(h, &rc, by, FEED, start, err, sizeof(err));
	assert_true(s.injected);
	if (e != -SH2000_EHEARTBEAT)
		fail_msg("the stall: %d (%s), expected EHEARTBEAT", e, err);
	/* the DSP runs again: it takes the emergency stop and sees the
	 * counter jump, which disables X */
	CHECK(sh2000_sim_inject(h, SH2000_INJECT_CLEAR, 0, 0));
	CHECK(sh2000_sleep_ns(h, 5000000ull));
}

/* X's carriage, per servo cycle, while Y's motion runs. */
struct coast {
	double y0;		/* Y's set-point at the first sample */
	int started;		/* Y's set-point has left y0 */
	double x_start, v_start;	/* X then: mm, mm/s */
	double x_prev, x_last, t_prev;
	int have_prev;
};

static void on_sample(void *ctx, const struct sh2000_run_sample *s)
{
	struct coast *c = ctx;

	if (!c->have_prev)
		c->y0 = s->cmd[1];
	if (!c->started && fabs(s->cmd[1] - c->y0) > 1e-6) {
		c->started = 1;
		c->x_start = s->act[0];
		c->v_start = c->have_prev && s->t > c->t_prev ?
			     (s->act[0] - c->x_prev) / (s->t - c->t_prev) : 0.0;
	}
	c->x_prev = s->act[0];
	c->t_prev = s->t;
	c->have_prev = 1;
	c->x_last = s->act[0];
}

static void next_run_while_coasting(void **state)
{
	const double by[SH2000_AXES] = { 0, 5.0, 0, 0 };
	struct sh2000 *h = simtest_open();
	struct sh2000_run_config rc;
	struct sh2000_status st;
	struct coast c = { 0 };
	double start[SH2000_AXES];
	char err[512];
	int e;

	(void)state;
	stall_while_x_moves(h);
	CHECK(sh2000_reset(h));
	CHECK(sh2000_enable(h, 0x2));
	CHECK(sh2000_poll(h, &st));
	assert_false(st.axis[0].state & SH2000_AXIS_ENABLED);
	sh2000_run_config_default(&rc);
	rc.sample = on_sample;
	rc.ctx = &c;
	e = run_line(h, &rc, by, 50.0, start, err, sizeof(err));
	if (e)
		fail_msg("the run on Y while X coasts: %d: %s", e, err);
	/* X did coast: fast when Y started, and further than FERR_LIMIT
	 * during Y's motion (what the records' X was compared with) */
	assert_true(c.started);
	printf("# X at Y's start: %.1f mm/s; coasted %.3f mm during the run\n",
	       c.v_start, fabs(c.x_last - c.x_start));
	assert_true(fabs(c.v_start) > 10.0);
	assert_true(fabs(c.x_last - c.x_start) > FERR_MM);
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_int_equal(st.card_faults, 0);
	assert_true(fabs(st.axis[1].cmd_mm - (start[1] + 5.0)) < 1e-5);
	sh2000_close(h);
}

/* A run whose records move X, which is disabled (at rest): the card
 * rejects it and the runner names X. */
static void disabled_axis_moved(void **state)
{
	const double by[SH2000_AXES] = { 5.0, 5.0, 0, 0 };
	struct sh2000 *h = simtest_open();
	struct sh2000_status st;
	double start[SH2000_AXES];
	char err[512];
	int e;

	(void)state;
	CHECK(sh2000_enable(h, 0x2));
	e = run_line(h, NULL, by, 50.0, start, err, sizeof(err));
	printf("# %s\n", err);
	assert_int_equal(e, -SH2000_EREJECTED);
	assert_non_null(strstr(err, "axis not enabled"));
	assert_non_null(strstr(err,
			       "axis X is disabled and the run's records move it over"));
	/* Y is enabled and moved: it is not named */
	assert_null(strstr(err, "axis Y"));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.reject_reason, SH2000_REJECT_DISABLED);
	assert_true(st.card_faults & SH2000_FAULT_REJECTED);
	/* the card did not drive X */
	assert_true(fabs(st.axis[0].pos_mm - start[0]) < 1e-6);
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(next_run_while_coasting),
		cmocka_unit_test(disabled_axis_moved),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
