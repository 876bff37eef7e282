/* SPDX-License-Identifier: MIT */
/* Helpers for the tests that drive the card model through the library. */
#ifndef SH2000_TEST_SIMTEST_H
#define SH2000_TEST_SIMTEST_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000/sim.h"
#include "sh2000/run.h"

#define CHECK(call) do { \
	int r_ = (call); \
	if (r_ < 0) \
		fail_msg("%s = %d (%s): %s", #call, r_, sh2000_strerror(r_), \
			 sh2000_last_error(h)); \
} while (0)

static inline struct sh2000 *simtest_open(void)
{
	struct sh2000 *h = NULL;
	char msg[256];
	int r = sh2000_open(&h, "sim", msg, sizeof(msg));

	if (r < 0)
		fail_msg("open sim: %d %s", r, msg);
	return h;
}

/* Set-points of all axes now (counts). */
static inline void simtest_cmd(struct sh2000 *h, int32_t p[SH2000_AXES])
{
	struct sh2000_status st;
	unsigned int a;

	CHECK(sh2000_poll(h, &st));
	for (a = 0; a < SH2000_AXES; a++)
		p[a] = st.axis[a].cmd_counts;
}

/*
 * Push n points moving `axis` by `step` counts per coarse period from p
 * (p is updated), in batches of `batch`, waiting for room. Returns the
 * last push result.
 */
static inline int simtest_line(struct sh2000 *h, int32_t p[SH2000_AXES],
			       unsigned int axis, int32_t step, size_t n,
			       size_t batch, unsigned int flags)
{
	int32_t pts[SH2000_RING_RECORDS][SH2000_AXES];
	size_t done = 0, i, k;
	int r = 0;

	while (done < n) {
		k = n - done < batch ? n - done : batch;
		r = sh2000_wait_space(h, (unsigned int)k, 10000);
		if (r < 0)
			return r;
		for (i = 0; i < k; i++) {
			p[axis] += step;
			memcpy(pts[i], p, sizeof(pts[i]));
		}
		r = sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])pts,
				       k, done + k == n ? flags : 0);
		if (r < 0)
			return r;
		done += k;
	}
	return r;
}

/* The RAM word a RAM flip hits in the record pushed last, given the ring's
 * HEAD (the number of the next record): its first position word. */
static inline unsigned int simtest_last_record_word(uint64_t head)
{
	return SH2000_W_RING_BASE +
	       (unsigned int)((head - 1) % SH2000_RING_RECORDS) *
	       SH2000_RECORD_WORDS + SH2000_REC_POS_LO(0);
}

/*
 * The fault matrices' LinuxCNC-style host: one record per coarse period
 * (2 ms) on a fixed schedule, speeding up along X to `feed` mm/s in 20
 * periods and keeping `ahead` records queued, as a servo thread pushes.
 * at(ctx) runs once, right after record `at_point` was pushed. Ends with
 * the first error (a poll, the card's status, a push, a sleep), or 0
 * after max_points records.
 */
struct simtest_period {
	double feed;
	unsigned int ahead, at_point, max_points;
	void (*at)(void *ctx);
	void *ctx;
};

static inline int simtest_period(struct sh2000 *h,
				 const struct simtest_period *c)
{
	const double step_mm = c->feed * 0.002, scale = 1e5;
	struct sh2000_status st;
	int32_t p[SH2000_AXES];
	double x = 0.0, v = 0.0;
	uint64_t next, now;
	unsigned int i = 0;
	int e = 0;

	simtest_cmd(h, p);
	next = sh2000_now_ns(h);
	while (i < c->max_points && !e) {
		e = sh2000_poll(h, &st);
		if (!e)
			e = sh2000_status_error(h, &st);
		if (e)
			break;
		do {
			v = v + step_mm / 20.0 < step_mm ? v + step_mm / 20.0 :
							   step_mm;
			x += v;
			p[0] = (int32_t)llround(x * scale);
			e = sh2000_push_counts(h,
					       (const int32_t (*)[SH2000_AXES])&p,
					       1, 0);
			if (e > 0)
				e = 0;
			if (!e && ++i == c->at_point)
				c->at(c->ctx);
		} while (!e && ++st.queue_fill < c->ahead);
		next += 2000000ull;
		now = sh2000_now_ns(h);
		if (!e && next > now)
			e = sh2000_sleep_ns(h, next - now);
	}
	return e;
}

/* After a fault: reset, enable, a 5 mm line along Y at 50 mm/s through
 * the runner; it must end idle at its end. */
static inline void simtest_next_run(struct sh2000 *h)
{
	struct sh2000_path_config pc;
	struct sh2000_status st;
	struct sh2000_run *r;
	double end[4];
	char msg[256];
	unsigned int a;

	CHECK(sh2000_reset(h));
	CHECK(sh2000_enable(h, 0xf));
	CHECK(sh2000_run_path_config(h, &pc));
	if (sh2000_run_create(&r, h, &pc, NULL, msg, sizeof(msg)) < 0)
		fail_msg("next run: %s", msg);
	for (a = 0; a < 4; a++)
		end[a] = pc.start[a] + (a == 1 ? 5.0 : 0.0);
	CHECK(sh2000_path_line(sh2000_run_path(r), end, 50.0));
	if (sh2000_run_finish(r) != 0)
		fail_msg("next run: %s", sh2000_run_error(r));
	CHECK(sh2000_poll(h, &st));
	assert_int_equal(st.card_state, SH2000_STATE_IDLE);
	assert_true(fabs(st.axis[1].cmd_mm - end[1]) < 1e-5);
	sh2000_run_destroy(r);
}

#endif
