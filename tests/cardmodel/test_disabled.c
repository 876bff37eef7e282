// SPDX-License-Identifier: MIT
/*
 * REJECT_DISABLED (docs/protocol.md 7.4): the records must not move a
 * disabled axis, which the card does not drive. Within a motion they hold
 * it where its first record put it (within FERR_LIMIT), or follow its
 * encoder (within FERR_LIMIT); the first record is not compared with the
 * encoder, since a carriage the card let go of coasts on.
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

#define MAXPTS	1000
#define FERR	20000.0		/* the default FERR_LIMIT, counts */

static int32_t pts[MAXPTS][SH2000_AXES];
static double xs[MAXPTS];

/* A 5 mm move of axis 1 at 50 mm/s; the other axes at `hold`. */
static unsigned int move_axis1(const int32_t hold[SH2000_AXES])
{
	unsigned int n = h_trapezoid(0, 5e5, 5e6, 5e8, 0.002, xs, MAXPTS), i;

	for (i = 0; i < n; i++) {
		memcpy(pts[i], hold, sizeof(pts[i]));
		pts[i][1] = (int32_t)lrint(xs[i]);
	}
	return n;
}

static int64_t act(struct harness *h, unsigned int a)
{
	return h->fw->dsp.ax[a].act;
}

static void no_rejection(struct harness *h)
{
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_word(h, SH2000_W_REJECT_COUNT), 0);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
}

/* Axis 2, disabled at 0, held at 0.5 mm by every record: not moved. */
static void held_anywhere(void **state)
{
	struct harness *h = *state;
	int32_t hold[SH2000_AXES] = { 0, 0, 50000, 0 }, cmd[SH2000_AXES];
	uint32_t pos[SH2000_AXES];
	unsigned int n = move_axis1(hold);

	h_stream(h, (const int32_t (*)[SH2000_AXES])pts, n, 100000);
	no_rejection(h);
	/* the card did not drive it: its set-point is its encoder */
	h_snapshot(h, cmd, pos);
	assert_int_equal(cmd[2], 0);
	assert_int_equal(pos[2], 0);
	assert_int_equal(cmd[1], 500000);
}

/* Axis 2 disabled at 0; its records start at 1 mm (accepted) and go
 * 0.05 mm further each: rejected at the first more than FERR_LIMIT from
 * that start, seq 5 (0.25 mm). */
static void moved_rejected(void **state)
{
	struct harness *h = *state;
	int32_t hold[SH2000_AXES] = { 0, 0, 0, 0 };
	unsigned int n = move_axis1(hold), i;

	for (i = 0; i < n; i++)
		pts[i][2] = 100000 + (int32_t)(i * 5000);
	h_stream(h, (const int32_t (*)[SH2000_AXES])pts, n, 100000);
	assert_int_equal(h_word(h, SH2000_W_REJECT_COUNT), 1);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), 5);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON),
			 SH2000_REJECT_DISABLED);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
	assert_int_equal(act(h, 2), 0);
}

/*
 * Axis 0 cruising at v counts/s when a counter glitch disables it (the
 * card stops, the carriage coasts on); then RESET. Axis 1 stays enabled.
 */
static void let_go_at(struct harness *h, double v)
{
	unsigned int n = h_trapezoid(0, 4e6, v, 5e8, 0.002, xs, MAXPTS), i;
	unsigned int cruise = (unsigned int)(v / 5e8 / 0.002) + 5;

	for (i = 0; i < n; i++) {
		pts[i][0] = (int32_t)lrint(xs[i]);
		pts[i][1] = pts[i][2] = pts[i][3] = 0;
		assert_int_equal(h_push(h, pts[i], (uint16_t)i, 0), 0);
		if (i >= cruise)
			break;
	}
	h_cycles(h, 20 * cruise);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_RUNNING);
	sh2000_fw_inject(h->fw, SH2000_INJECT_COUNTER_GLITCH, 0, 0);
	h_cycles(h, 20);
	assert_false(h_word(h, SH2000_W_AXIS_STATE(0)) & SH2000_AXIS_ENABLED);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
}

/* The case that once failed: a move on axis 1 right after the reset, axis 0 held
 * where the host read it while its carriage coasts on. */
static void coasting_held(void **state)
{
	struct harness *h = *state;
	int32_t hold[SH2000_AXES] = { 0, 0, 0, 0 }, cmd[SH2000_AXES];
	uint32_t pos[SH2000_AXES];
	unsigned int n;
	int64_t x0, x1;

	let_go_at(h, 1e7);			/* 100 mm/s */
	h_snapshot(h, cmd, pos);
	hold[0] = (int32_t)pos[0];
	x0 = act(h, 0);
	n = move_axis1(hold);
	h_stream(h, (const int32_t (*)[SH2000_AXES])pts, n, 100000);
	x1 = act(h, 0);
	printf("# axis 0 coasted %.3f mm during the move\n",
	       (double)(x1 - x0) * 1e-5);
	no_rejection(h);
	assert_true((double)(x1 - x0) > 2.0 * FERR);
	h_snapshot(h, cmd, pos);
	assert_int_equal(cmd[1], 500000);
}

/* A host that sends the position it reads of a disabled axis (LinuxCNC's
 * driver does): its records follow the coasting carriage further than
 * FERR_LIMIT from the first, within FERR_LIMIT of the encoder. */
static void follows_encoder(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 }, cmd[SH2000_AXES];
	uint32_t pos[SH2000_AXES];
	int32_t first = 0;
	unsigned int i;

	let_go_at(h, 2e6);			/* 20 mm/s */
	for (i = 0; i < 100; i++) {
		h_snapshot(h, cmd, pos);
		p[0] = (int32_t)pos[0];
		p[1] += 100;
		if (i == 0)
			first = p[0];
		assert_int_equal(h_push(h, p, (uint16_t)i,
					i == 99 ? SH2000_REC_F_END : 0), 0);
		h_cycles(h, i == 0 ? 1 : 20);
	}
	h_cycles(h, 200);
	printf("# records followed axis 0 over %.3f mm\n",
	       (double)(p[0] - first) * 1e-5);
	no_rejection(h);
	assert_true(fabs((double)(p[0] - first)) > FERR);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(held_anywhere, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(moved_rejected, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(coasting_held, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(follows_encoder, h_setup_enabled, h_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
