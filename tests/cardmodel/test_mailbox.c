// SPDX-License-Identifier: MIT
/* The point mailbox (protocol 1.3, docs/protocol.md 7.6): posts and ring
 * records interleaved make one queue, each record taken exactly once; a
 * post not yet published (SEQ unwritten), a stale one, a damaged one, a
 * misnumbered one and one into a full queue are never played as a new
 * point. Ring records follow a post without waiting for the card. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "harness.h"

#define MAXPTS 2000
#define STEPS 20	/* the harness' fine steps per coarse period */
static int32_t pts[MAXPTS][SH2000_AXES];
static double xs[MAXPTS];

static void mbox_write(struct harness *h, const uint16_t *m, unsigned int n)
{
	unsigned int i;

	for (i = 0; i < n; i++)
		sh2000_dpram_write(h->ram, SH2000_W_MBOX + i, m[i]);
}

/* The ring is the way for every fourth point, the END, and whenever the
 * card has not received everything yet (a post waits for that, ring
 * records do not: they follow a post at once); the mailbox for the rest. */
static unsigned int stream_mixed(struct harness *h, unsigned int n,
				 unsigned int *posts)
{
	unsigned int next = 0, cycles = 0;

	*posts = 0;
	while (cycles < 100000) {
		while (next < n && h_fill(h) < 8) {
			/* (and while the mailbox holds this number's SEQ:
			 * the card would see no change) */
			int ring = next % 4 == 3 || next + 1 == n ||
				   h_word(h, SH2000_W_POSTED) != h->head ||
				   h_word(h, SH2000_W_MBOX + SH2000_MBOX_SEQ) == h->head;

			if (ring)
				assert_int_equal(h_push(h, pts[next], h->head,
							next + 1 == n ? SH2000_REC_F_END : 0), 0);
			else
				assert_int_equal(h_post(h, pts[next]), 0);
			*posts += !ring;
			next++;
		}
		h_cycles(h, 1);
		cycles++;
		if (next == n && h_word(h, SH2000_W_STATE) != SH2000_STATE_RUNNING)
			break;
	}
	return cycles;
}

static void interleaved_with_ring(void **state)
{
	struct harness *h = *state;
	unsigned int n = h_trapezoid(0, 2e6, 3e7, 3e8, 0.002, xs, MAXPTS);
	unsigned int start, j, k, a, posts;
	uint16_t first = h->head, rejects = h_word(h, SH2000_W_REJECT_COUNT);
	double seq[2][MAXPTS + 5];

	for (j = 0; j < n; j++) {
		/* far from 0 and negative on axis 1: the 20-bit steps carry
		 * whole 32-bit positions */
		pts[j][0] = (int32_t)lrint(xs[j]);
		pts[j][1] = -(int32_t)lrint(xs[j] / 2);
		pts[j][2] = pts[j][3] = 0;
	}
	h_trace(h, 100000);
	stream_mixed(h, n, &posts);
	printf("# %u points, %u through the mailbox\n", n, posts);
	assert_true(posts > n / 4);
	for (a = 0; a < 2; a++) {
		seq[a][0] = seq[a][1] = seq[a][2] = 0.0;
		for (j = 0; j < n; j++)
			seq[a][j + 3] = pts[j][a];
		seq[a][n + 3] = seq[a][n + 4] = pts[n - 1][a];
	}
	for (start = 0; start < h->trace_len; start++)
		if (h->trace[start].state == SH2000_STATE_RUNNING)
			break;
	assert_true(start + (n + 2) * STEPS <= h->trace_len);
	/* every record once, in order: the set-points are their B-spline */
	for (j = 0; j < n + 2; j++)
		for (k = 1; k <= STEPS; k++) {
			const struct sh2000_probe *p = &h->trace[start + j * STEPS + k - 1];

			for (a = 0; a < 2; a++) {
				const double *w = &seq[a][j];

				assert_true(fabs(p->axis[a].fine_cmd -
						 sh2000_bspline(w[0], w[1], w[2], w[3],
								k / (double)STEPS)) < 1e-6);
			}
		}
	assert_int_equal(h->trace[start + (n + 2) * STEPS - 1].state, SH2000_STATE_IDLE);
	h_cycles(h, 1000);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_word(h, SH2000_W_REJECT_COUNT), rejects);
	assert_int_equal(h_word(h, SH2000_W_POSTED), (uint16_t)(first + n));
	assert_int_equal(h_word(h, SH2000_W_TAIL), (uint16_t)(first + n));
}

/* Words written, SEQ not yet: nothing. SEQ written: one record, and the
 * mailbox left as it is is never taken again. */
static void torn_and_stale(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	uint16_t m[SH2000_MBOX_WORDS], n0;

	/* a motion through the ring first: the count leaves the mailbox's
	 * SEQ (0 in a fresh RAM) behind */
	assert_int_equal(h_push(h, p, h->head, SH2000_REC_F_END), 0);
	h_cycles(h, 5000);
	n0 = h->head;
	sh2000_mbox_pack(m, p, h->head);
	mbox_write(h, m, SH2000_MBOX_SEQ);
	h_cycles(h, 200);
	assert_int_equal(h_word(h, SH2000_W_POSTED), n0);
	assert_int_equal(h_word(h, SH2000_W_TAIL), n0);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);

	mbox_write(h, m, SH2000_MBOX_WORDS);
	h->head++;
	h_cycles(h, 1);
	assert_int_equal(h_word(h, SH2000_W_POSTED), (uint16_t)(n0 + 1));
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_RUNNING);
	assert_int_equal(h_push(h, p, h->head, SH2000_REC_F_END), 0);
	h_cycles(h, 5000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_IDLE);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
	assert_int_equal(h_word(h, SH2000_W_POSTED), (uint16_t)(n0 + 2));
	assert_int_equal(h_word(h, SH2000_W_TAIL), (uint16_t)(n0 + 2));
	/* HEAD put level with POSTED is no publication */
	sh2000_dpram_write(h->ram, SH2000_W_HEAD, h->head);
	h_cycles(h, 100);
	assert_int_equal(h_word(h, SH2000_W_POSTED), (uint16_t)(n0 + 2));
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);
}

/* A few ring records from 0, then `m` posted as the next record. */
static uint16_t post_after_ring(struct harness *h, uint16_t *m, int corrupt,
				int renumber)
{
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	uint16_t num;
	unsigned int i;

	for (i = 1; i < 5; i++) {
		p[0] = (int32_t)(i * 1000);
		assert_int_equal(h_push(h, p, h->head, 0), 0);
	}
	h_cycles(h, 1);
	num = h->head;
	p[0] = 5000;
	sh2000_mbox_pack(m, p, (uint16_t)(num + renumber));
	if (corrupt)
		m[SH2000_MBOX_POS_LO(0)] ^= 0x40;	/* after the check */
	mbox_write(h, m, SH2000_MBOX_WORDS);
	h->head++;
	h_cycles(h, 1);
	return num;
}

static void expect_refused(struct harness *h, uint16_t num, uint16_t reason)
{
	uint16_t rejects = h_word(h, SH2000_W_REJECT_COUNT);

	h_cycles(h, 6 * STEPS);
	assert_int_equal((uint16_t)(h_word(h, SH2000_W_REJECT_COUNT) - rejects), 1);
	assert_int_equal(h_word(h, SH2000_W_REJECT_SEQ), num);
	assert_int_equal(h_word(h, SH2000_W_REJECT_REASON), reason);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_REJECTED);
	assert_int_equal(h_fill(h), 0);
	/* the card never played it: its set-point stayed below 4000 */
	assert_true(h->fw->dsp.ax[0].cmd <= 4000.0);
	h_cycles(h, 2000);
	assert_int_equal(h_word(h, SH2000_W_STATE), SH2000_STATE_FAULT);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
}

static void damaged_refused(void **state)
{
	struct harness *h = *state;
	uint16_t m[SH2000_MBOX_WORDS];
	uint16_t num = post_after_ring(h, m, 1, 0);

	expect_refused(h, num, SH2000_REJECT_CHECKSUM);
}

/* Numbered one ahead: the post before it never reached the RAM. */
static void misnumbered_refused(void **state)
{
	struct harness *h = *state;
	uint16_t m[SH2000_MBOX_WORDS];
	uint16_t num = post_after_ring(h, m, 0, 1);

	expect_refused(h, num, SH2000_REJECT_DROPPED);
}

/* A post into a full queue, and HEAD moved behind POSTED: host bugs. */
static void protocol_faults(void **state)
{
	struct harness *h = *state;
	int32_t p[SH2000_AXES] = { 0, 0, 0, 0 };
	uint16_t m[SH2000_MBOX_WORDS];
	unsigned int i;

	for (i = 0; i < SH2000_RING_RECORDS; i++)
		assert_int_equal(h_push(h, p, h->head, 0), 0);
	h_cycles(h, 1);		/* received, the first one consumed */
	assert_int_equal(h_push(h, p, h->head, 0), 0);
	h_cycles(h, 1);
	assert_int_equal(h_fill(h), SH2000_RING_RECORDS);
	assert_int_equal(h_post(h, p), -1);
	sh2000_mbox_pack(m, p, h->head);
	mbox_write(h, m, SH2000_MBOX_WORDS);
	h->head++;
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_PROTOCOL);
	assert_int_equal(h_word(h, SH2000_W_TAIL), h->head);
	assert_int_equal(h_word(h, SH2000_W_POSTED), h->head);
	h_cycles(h, 2000);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	assert_int_equal(h_word(h, SH2000_W_FAULTS), 0);

	sh2000_dpram_write(h->ram, SH2000_W_HEAD, (uint16_t)(h->head - 3u));
	h_cycles(h, 1);
	assert_true(h_word(h, SH2000_W_FAULTS) & SH2000_FAULT_PROTOCOL);
}

/* A position rides as its low 20 bits; nearest the previous one it is
 * the whole value, for every step within SH2000_MBOX_STEP_MAX. */
static void positions_from_steps(void **state)
{
	static const int32_t refs[] = { 0, 1, -1, 123456789, -987654321,
					INT32_MAX, INT32_MIN, 0x7fff0000 };
	static const int32_t steps[] = { 0, 1, -1, 4095, -65536,
					 SH2000_MBOX_STEP_MAX,
					 -SH2000_MBOX_STEP_MAX };
	unsigned int i, j, a;

	(void)state;
	for (i = 0; i < sizeof(refs) / sizeof(refs[0]); i++)
		for (j = 0; j < sizeof(steps) / sizeof(steps[0]); j++) {
			int32_t pos[SH2000_AXES];
			uint16_t m[SH2000_MBOX_WORDS];

			for (a = 0; a < SH2000_AXES; a++)
				pos[a] = (int32_t)((uint32_t)refs[i] +
						   (uint32_t)(steps[j] * (a % 2 ? -1 : 1)));
			sh2000_mbox_pack(m, pos, 7);
			assert_int_equal(m[SH2000_MBOX_CHECK], sh2000_mbox_check(m));
			for (a = 0; a < SH2000_AXES; a++)
				assert_int_equal(sh2000_mbox_position(m, a, refs[i]),
						 pos[a]);
		}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(interleaved_with_ring, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(torn_and_stale, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(damaged_refused, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(misnumbered_refused, h_setup_enabled, h_teardown),
		cmocka_unit_test_setup_teardown(protocol_faults, h_setup_enabled, h_teardown),
		cmocka_unit_test(positions_from_steps),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
