// SPDX-License-Identifier: MIT
/* Streaming: the fine set-points are the B-spline of the records, END
 * reaches the end point exactly, following error with and without
 * feed-forward, and each reason a record is rejected. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

#define MAXPTS 4000
static int32_t pts[MAXPTS][SH2000_AXES];
static double xs[MAXPTS];

/* A diagonal move on axes 0 and 1 (axis 1 at half the distance). */
static unsigned int make_move(double dist, double v, double a)
{
	unsigned int n = h_trapezoid(0, dist, v, a, 0.002, xs, MAXPTS), i;

	for (i = 0; i < n; i++) {
		pts[i][0] = (int32_t)lrint(xs[i]);
		pts[i][1] = (int32_t)lrint(xs[i] / 2);
		pts[i][2] = pts[i][3] = 0;
	}
	return n;
}

static void follows_bspline(void **state)
{
	struct harness *h = *state;
	unsigned int n = make_move(2e6, 3e7, 3e8), start, j, k, a;
	double seq[SH2000_AXES][MAXPTS + 5];

	h_trace(h, 100000);
	h_stream(h, pts, n, 100000);
	for (a = 0; a < 2; a++) {
		for (j = 0; j < 3; j++)
			seq[a][j] = 0.0;
		for (j = 0; j < n; j++)
			seq[a][j + 3] = pts[j][a];
		seq[a][n + 3] = seq[a][n + 4] = pts[n - 1][a];
	}
	for (start = 0; start < h->trace_len; start++)
		if (h->trace[start].state == SH2000_STATE_RUNNING)
			break;
	assert_true(start < h->trace_len);
	for (j = 0; j < n + 2; j++)
		for (k = 1; k <= 20; k++) {
			const struct sh2000_probe *p = &h->trace[start + j * 20 + k - 1];

			for (a = 0; a < 2; a++) {
				const double *w = &seq[a][j];
				double x = sh2000_bspline(w[0], w[1], w[2], w[3], k / 20.0);

				assert_true(fabs(p->axis[a].fine_cmd - x) < 1e-6);
			}
		}
	/* END: the end point exactly, then idle without an underrun */
	assert_true(h->trace[start + (n + 2) * 20 - 1].axis[0].fine_cmd == pts[n - 1][0]);
	assert_true(h->trace[start + (n + 2) * 20 - 1].axis[1].fine_cmd == pts[n - 1][1]);
	assert_int_equal(h->trace[start + (n + 2) * 20 - 1].state, SH2000_STATE_IDLE);
	assert_int_equal(h->trace[start + (n + 2) * 20 - 2].state, SH2000_STATE_RUNNING);
	h_cycles(h, 1000);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	{
		int32_t cmd[SH2000_AXES];
		uint32_t act[SH2000_AXES];

		h_snapshot(h, cmd, act);
		assert_int_equal(cmd[0], pts[n - 1][0]);
		assert_true(abs(sh2000_counter_delta(act[0], (uint32_t)pts[n - 1][0])) <= 2);
	}
}

static double max_ferr(struct harness *h, int ff)
{
	unsigned int n = make_move(1e7, 3e7, 3e8), i;
	double m = 0.0;

	if (!ff) {
		h_set_f(h, 0, SH2000_P_KVFF, 0.0);
		h_set_f(h, 0, SH2000_P_KAFF, 0.0);
	}
	h_trace(h, 200000);
	h_stream(h, pts, n, 200000);
	for (i = 0; i < h->trace_len; i++) {
		double e = fabs(h->trace[i].axis[0].fine_cmd - h->trace[i].axis[0].actual);

		if (e > m)
			m = e;
	}
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	return m;
}

static void following_error(void **state)
{
	struct harness *h = *state;
	double ff = max_ferr(h, 1), pid;

	h_fini(h);
	assert_int_equal(h_setup_enabled(state), 0);
	h = *state;
	pid = max_ferr(h, 0);
	printf("# 100 mm at 300 mm/s, 3 m/s^2: max following error PID %.0f counts (%.2f um), "
	       "PID+FF %.1f counts (%.3f um)\n", pid, pid / 100.0, ff, ff / 100.0);
	assert_true(ff < 100.0);	/* < 1 um */
	assert_true(pid > 10.0 * ff);
}

static void expect_reject(struct harness *h, uint16_t seq, uint16_t reason)
{
	printf("# rejected seq %u: %s\n", h_word(h, SH2000_W_REJECT_SEQ),
	       sh2000_reject_name(h_word(h, SH2000_W_REJECT_REASON)));
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), seq);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), reason);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
	assert_int_equal(h_fill(h), 0);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
}

/* Streams a few good records, then `bad` at seq 10. */
static void run_bad(struct harness *h, const int32_t bad[SH2000_AXES], uint16_t flags,
		    int corrupt_check)
{
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	uint16_t count = h_word(h, SH2000_W_REJECT_COUNT);
	unsigned int i;

	/* start from 0 whatever the previous case left */
	assert_int_equal(h_cmd(h, SH2000_CMD_SET_POSITION, 0, 0, 0, NULL), SH2000_RES_OK);

	for (i = 1; i < 10; i++) {
		p[0] = (int32_t)(i * 1000);
		h_push(h, p, (uint16_t)i, 0);
	}
	h_push(h, bad, 10, flags);
	if (corrupt_check) {
		unsigned int w = SH2000_W_RING_BASE +
				 ((uint16_t)(h->head - 1) % SH2000_RING_RECORDS) *
					 SH2000_RECORD_WORDS + SH2000_REC_CHECK;

		sh2000_dpram_write(h->ram, w, (uint16_t)(h_word(h, w) ^ 1));
	}
	p[0] = 50000;
	h_push(h, p, 11, SH2000_REC_F_END);
	h_cycles(h, 20 * 10 + 1);
	assert_int_equal((uint16_t)(h_word(h, SH2000_W_REJECT_COUNT) - count), 1);
}

static void rejections(void **state)
{
	struct harness *h = *state;
	int32_t bad[SH2000_AXES] = { 10000, 0, 0, 0 };
	double step = 4e7 * 0.002;	/* VMAX * coarse period */

	run_bad(h, bad, 0, 1);
	expect_reject(h, 10, SH2000_REJECT_CHECKSUM);
	run_bad(h, bad, 0x8000, 0);
	expect_reject(h, 10, SH2000_REJECT_RESERVED);
	/* within the 5% margin: accepted */
	bad[0] = (int32_t)(h->fw->dsp.ax[0].act + step * 1.04);
	{
		int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };

		p[0] = (int32_t)h->fw->dsp.ax[0].act;
		h_push(h, p, 1, 0);
		h_push(h, bad, 2, SH2000_REC_F_END);
		h_cycles(h, 200);
		assert_int_equal(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED, 0);
		h_cycles(h, 2000);
	}
	run_bad(h, (int32_t[]){ 9000 + (int32_t)(step * 1.06), 0, 0, 0 }, 0, 0);
	expect_reject(h, 10, SH2000_REJECT_VELOCITY);
	assert_int_equal(h_set_i(h, 0, SH2000_P_SOFT_MAX, 9500), SH2000_RES_OK);
	run_bad(h, bad, 0, 0);
	expect_reject(h, 10, SH2000_REJECT_SOFT_LIMIT);
	assert_int_equal(h_set_i(h, 0, SH2000_P_SOFT_MAX, 2147483647), SH2000_RES_OK);
	/* axis 2 is disabled: it may only "move" within FERR_LIMIT of where it is */
	run_bad(h, (int32_t[]){ 10000, 0, 50000, 0 }, 0, 0);
	expect_reject(h, 10, SH2000_REJECT_DISABLED);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(follows_bspline, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(following_error, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(rejections, h_setup_enabled, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
