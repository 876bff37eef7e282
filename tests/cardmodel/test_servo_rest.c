// SPDX-License-Identifier: MIT
/*
 * The servo against the true carriage, in virtual time: a move at the
 * compensation benchmark's speed to a set-point off whole counts (as a
 * compensation table's corrected set-point is), then a long rest. What
 * is measured is the carriage itself (the plant's position), not the
 * counter: how far past the set-point it overshoots when the set-point
 * stops, and where it rests against the set-point and how far it
 * wanders there (a loop on the counter alone can only hold a count's
 * edge, and hunts across it).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

#define COUNTS_PER_MM	100000.0
#define REST_CYCLES	10000	/* 1 s at rest after the move */
#define SETTLED_CYCLES	300	/* 30 ms: the benchmark's settling time */

struct watch {
	struct harness *h;
	double x0_mm, act0;	/* the carriage and its count at the start */
	double target;		/* the set-point at rest, counts */
	double dir;		/* +1 moving up, -1 down */
	int stopped;		/* the set-point has stopped */
	unsigned int rest;	/* cycles since it stopped */
	double over;		/* largest overshoot past the target, counts */
	double ferr;		/* largest |set-point - counter| moving */
	double rest_lo, rest_hi;	/* carriage after settling, counts */
	double act_lo, act_hi;		/* the counter after settling */
};

static double carriage_counts(const struct watch *w)
{
	double tool[SH2000_AXES];

	sh2000_fw_tool_position(w->h->fw, tool);
	return (tool[0] - w->x0_mm) * COUNTS_PER_MM + w->act0;
}

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct watch *w = ctx;
	double x = carriage_counts(w);

	if (!w->stopped) {
		w->ferr = fmax(w->ferr, fabs(p->axis[0].fine_cmd +
					     w->h->fw->dsp.comp.off[0] -
					     p->axis[0].actual));
		return;
	}
	w->rest++;
	if (w->rest < SETTLED_CYCLES) {
		w->over = fmax(w->over, w->dir * (x - w->target));
		return;
	}
	w->rest_lo = fmin(w->rest_lo, x - w->target);
	w->rest_hi = fmax(w->rest_hi, x - w->target);
	w->act_lo = fmin(w->act_lo, p->axis[0].actual);
	w->act_hi = fmax(w->act_hi, p->axis[0].actual);
}

/* Axis 0 from where it stands by dist mm at 40 mm/s, 5 m/s^2, its
 * set-point offset by frac counts (as a compensation table's correction
 * offsets it: no table is loaded, so the firmware keeps the offset as it
 * is set here); then REST_CYCLES at rest. */
static void move_and_rest(struct harness *h, struct watch *w, double dist,
			  double frac)
{
	static double pts[4000];
	static int32_t rec[4000][SH2000_AXES];
	int32_t cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES];
	unsigned int n, i, a;

	h_snapshot(h, cmd, act);
	h->fw->dsp.comp.off[0] = frac;
	n = h_trapezoid(cmd[0], cmd[0] + dist * COUNTS_PER_MM, 40.0 * COUNTS_PER_MM,
			5000.0 * COUNTS_PER_MM, 1e-3, pts, 4000);
	for (i = 0; i < n; i++)
		for (a = 0; a < SH2000_AXES; a++)
			rec[i][a] = a == 0 ? (int32_t)lrint(pts[i]) : cmd[a];
	w->target = rec[n - 1][0] + frac;
	w->dir = dist > 0 ? 1.0 : -1.0;
	w->stopped = 0;
	w->rest = 0;
	w->over = -1e9;
	w->ferr = 0.0;
	w->rest_lo = w->act_lo = 1e18;
	w->rest_hi = w->act_hi = -1e18;
	h_stream(h, (const int32_t (*)[SH2000_AXES])rec, n, 100000);
	w->stopped = 1;
	h_cycles(h, REST_CYCLES);
}

static void stop_and_rest(void **state)
{
	struct harness *h = *state;
	static const double frac[] = { 0.5, 0.3, 0.8, 0.05, 0.95, 0.0 };
	static const double dist[] = { 10.0, -7.0, 3.0, -1.0, 0.5, -20.0 };
	struct watch w = { .h = h };
	double tool[SH2000_AXES];
	int32_t cmd[SH2000_AXES];
	uint32_t act[SH2000_AXES];
	unsigned int i;

	h_snapshot(h, cmd, act);
	sh2000_fw_tool_position(h->fw, tool);
	w.x0_mm = tool[0];
	w.act0 = (double)(int32_t)act[0];
	sh2000_fw_set_observer(h->fw, observe, &w);
	for (i = 0; i < sizeof(frac) / sizeof(frac[0]); i++) {
		move_and_rest(h, &w, dist[i], frac[i]);
		printf("# stop %+.1f mm at %.2f count: following error %.2f counts, overshoot %.2f counts; at rest the carriage %+.3f..%+.3f counts from the set-point, the counter over %.0f counts\n",
		       dist[i], frac[i], w.ferr, w.over, w.rest_lo, w.rest_hi,
		       w.act_hi - w.act_lo + 1);
		/* the feed-forward leads the DAC's hold: the carriage follows
		 * the decelerating set-point within its count (the reading's
		 * floor and a count of jerk), no overshoot beyond that */
		assert_true(w.ferr <= 2.0);
		assert_true(w.over <= 1.0);
		/* the loop closes on the observer's reading, finer than a
		 * count, and the DAC's codes average to its output: the
		 * carriage rests in the middle of the set-point's count
		 * (S + 1/2, whatever S's fraction), within a twentieth of a
		 * count, still; the counter on one count or two beside it */
		assert_true(w.rest_lo >= 0.45 && w.rest_hi <= 0.55);
		assert_true(w.act_hi - w.act_lo <= 1.0);
	}
	sh2000_fw_set_observer(h->fw, NULL, NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(stop_and_rest, h_setup_enabled,
						h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
