// SPDX-License-Identifier: MIT
/*
 * Data gathering (protocol 1.2) on the card model, driven through the RAM
 * as a host would: a gathered record equals the firmware's own signals
 * sample for sample (each compared with what it means, from the probe and
 * the firmware's state seen by an observer), the triggers and the
 * pre-trigger ring, the sample period, and every refusal.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "harness.h"

#define GLOBAL SH2000_AXIS_GLOBAL
#define MAXPTS 2000

/* What the observer saw in one servo cycle. */
struct seen {
	struct sh2000_probe p;
	double cmd_v[SH2000_AXES], cmd_a[SH2000_AXES], cmd_j[SH2000_AXES];
	/* the error the PID closed on: the observer's, finer than a count */
	double loop_e[SH2000_AXES];
	int running;		/* the B-spline ran: the feed-forward leads */
	double kp[SH2000_AXES], td[SH2000_AXES], kvff[SH2000_AXES],
		kaff[SH2000_AXES];
};

static struct seen *seen;
static unsigned int nseen, capseen;

static void observe(void *ctx, const struct sh2000_probe *p)
{
	const struct harness *h = ctx;
	const struct sh2000_dsp *d = &h->fw->dsp;
	struct seen *s;
	unsigned int a;

	if (nseen >= capseen)
		return;
	s = &seen[nseen++];
	s->p = *p;
	s->running = d->state == SH2000_STATE_RUNNING;
	for (a = 0; a < SH2000_AXES; a++) {
		s->cmd_v[a] = d->ax[a].cmd_v;
		s->cmd_a[a] = d->ax[a].cmd_a;
		s->cmd_j[a] = d->ax[a].cmd_j;
		s->loop_e[a] = d->ax[a].loop_e;
		s->kp[a] = d->ax[a].prm.kp;
		s->td[a] = d->ax[a].prm.td;
		s->kvff[a] = d->ax[a].prm.kvff;
		s->kaff[a] = d->ax[a].prm.kaff;
	}
}

/* The feed-forward of that cycle: the set-point's mean velocity and
 * acceleration over the servo period to come (firmware.c, servo()). */
static double ff_of(const struct seen *s, unsigned int a, double T)
{
	double v = s->cmd_v[a], acc = s->cmd_a[a] + s->cmd_j[a] * T / 2;

	if (s->running)
		v += s->cmd_a[a] * T / 2 + s->cmd_j[a] * T * T / 6;
	return s->kvff[a] * v + s->kaff[a] * acc;
}

static void watch(struct harness *h, unsigned int cap)
{
	free(seen);
	seen = calloc(cap, sizeof(*seen));
	assert_non_null(seen);
	capseen = cap;
	nseen = 0;
	sh2000_fw_set_observer(h->fw, observe, h);
}

/* The observed cycle whose servo_cycle number is c. */
static const struct seen *at_cycle(uint64_t c)
{
	unsigned int i;

	for (i = 0; i < nseen; i++)
		if (seen[i].p.servo_cycle == c)
			return &seen[i];
	fail_msg("cycle %llu not observed", (unsigned long long)c);
	return NULL;
}

static uint16_t gset(struct harness *h, uint16_t axis, uint16_t field,
		     uint32_t v)
{
	return h_cmd(h, SH2000_CMD_GATHER_SET, axis, field, v, NULL);
}

static uint32_t w32(const uint16_t *w)
{
	return (uint32_t)w[0] | ((uint32_t)w[1] << 16);
}

/* The window as the card left it after the last command; checks the
 * header (sequence, kind, check word) and returns the payload count. */
static unsigned int window(struct harness *h, uint16_t kind, uint16_t *w)
{
	unsigned int i, n;

	for (i = 0; i < SH2000_GATHER_WINDOW_WORDS; i++)
		w[i] = h_word(h, SH2000_W_GATHER_BASE + i);
	assert_int_equal(w[SH2000_GW_SEQ], h->seq);
	assert_int_equal(w[SH2000_GW_KIND], kind);
	n = w[SH2000_GW_COUNT];
	assert_true(n <= SH2000_GATHER_WINDOW_WORDS - SH2000_GW_HEADER);
	assert_int_equal(w[SH2000_GW_CHECK], sh2000_gather_check(w, n));
	return n;
}

struct rec {
	uint16_t state, record, values, mask[SH2000_AXES];
	uint32_t samples, trig_index, first_cycle, trig_cycle, period;
	uint32_t *v;		/* samples * values */
};

static void info(struct harness *h, struct rec *r)
{
	uint16_t w[SH2000_GATHER_WINDOW_WORDS], *p = &w[SH2000_GW_HEADER];
	uint32_t state;
	unsigned int a;

	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_INFO, 0, 0, 0, &state),
			 SH2000_RES_OK);
	assert_int_equal(window(h, SH2000_GATHER_KIND_INFO, w),
			 SH2000_GATHER_INFO_WORDS);
	r->state = w[SH2000_GW_STATE];
	assert_int_equal(r->state, state);
	r->record = w[SH2000_GW_RECORD];
	r->values = p[SH2000_GI_VALUES];
	r->period = p[SH2000_GI_PERIOD];
	for (a = 0; a < SH2000_AXES; a++)
		r->mask[a] = p[SH2000_GI_SIGNALS(a)];
	r->samples = w32(&p[SH2000_GI_SAMPLES_LO]);
	r->trig_index = w32(&p[SH2000_GI_TRIGGER_INDEX_LO]);
	r->first_cycle = w32(&p[SH2000_GI_FIRST_CYCLE_LO]);
	r->trig_cycle = w32(&p[SH2000_GI_TRIGGER_CYCLE_LO]);
	assert_int_equal(w32(&p[SH2000_GI_BUFFER_LO]),
			 SH2000_GATHER_BUFFER_VALUES);
}

/* The whole record, chunk by chunk through the window. */
static void read_all(struct harness *h, struct rec *r)
{
	uint32_t total, got = 0, n;
	uint16_t w[SH2000_GATHER_WINDOW_WORDS];
	unsigned int i;

	info(h, r);
	assert_int_equal(r->state, SH2000_GATHER_DONE);
	total = r->samples * r->values;
	r->v = calloc(total ? total : 1, sizeof(*r->v));
	while (got < total) {
		assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_READ, 0, 0, got, &n),
				 SH2000_RES_OK);
		assert_int_equal(window(h, SH2000_GATHER_KIND_DATA, w), 2 * n);
		assert_int_equal(w[SH2000_GW_RECORD], r->record);
		assert_int_equal(w32(&w[SH2000_GW_OFFSET_LO]), got);
		assert_true(n >= 1 && n <= SH2000_GATHER_CHUNK_VALUES);
		for (i = 0; i < n; i++)
			r->v[got + i] = w32(&w[SH2000_GW_HEADER + 2 * i]);
		got += n;
	}
	/* past the end: refused, the window keeps the last chunk */
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_READ, 0, 0, total, NULL),
			 SH2000_RES_BAD_VALUE);
}

static float f32(uint32_t b)
{
	float f;

	memcpy(&f, &b, sizeof(f));
	return f;
}

static int32_t pts[MAXPTS][SH2000_AXES];

/* A move of axis 0 by dist counts, axis 1 by -dist/3, into pts[]. */
static unsigned int move(double dist)
{
	static double xs[MAXPTS];
	unsigned int n = h_trapezoid(0, dist, 3e7, 3e8, 0.002, xs, MAXPTS), i;

	for (i = 0; i < n; i++) {
		pts[i][0] = (int32_t)lrint(xs[i]);
		pts[i][1] = (int32_t)lrint(-xs[i] / 3);
		pts[i][2] = pts[i][3] = 0;
	}
	return n;
}

static int32_t rounded(double x)
{
	return (int32_t)nearbyint(x);
}

/* One sample of axis a against the cycle it was taken in (and the one
 * before, for the differences). */
static void check_axis(const uint32_t *v, uint16_t mask, unsigned int a,
		       const struct seen *s, const struct seen *prev)
{
	const struct sh2000_probe_axis *pa = &s->p.axis[a];
	double T = 1e-4, e = pa->fine_cmd - pa->actual;
	double le = s->loop_e[a], le1 = prev->loop_e[a];
	float P = 0, I = 0, D = 0, FF = 0;
	unsigned int sig, k = 0;

	for (sig = 0; sig < SH2000_GATHER_SIGNALS; sig++) {
		uint32_t x;

		if (!(mask & (1u << sig)))
			continue;
		x = v[k++];
		switch (sig) {
		case SH2000_GS_SETPOINT:
			assert_int_equal((int32_t)x, rounded(pa->fine_cmd));
			break;
		case SH2000_GS_ENCODER:
			assert_int_equal((int32_t)x, (int32_t)pa->actual);
			break;
		case SH2000_GS_FERR:
			assert_true(f32(x) == (float)e);
			break;
		case SH2000_GS_DAC:
			assert_int_equal((int32_t)x, pa->dac);
			break;
		case SH2000_GS_PID_P:
			P = f32(x);
			assert_true(P == (float)(s->kp[a] * le));
			/* the observer's reading within the counter's count */
			assert_true(fabs(le - e) <= 0.5 + 1e-6);
			break;
		case SH2000_GS_PID_I:
			I = f32(x);
			break;
		case SH2000_GS_PID_D:
			D = f32(x);
			assert_true(fabs(D - s->kp[a] * s->td[a] / T * (le - le1)) <=
				    1e-6 * (1 + fabs(D)));
			break;
		case SH2000_GS_FF:
			FF = f32(x);
			assert_true(fabs(FF - ff_of(s, a, T)) <=
				    1e-6 * (1 + fabs(FF)));
			break;
		case SH2000_GS_VELOCITY:
			assert_true(fabs(f32(x) - (pa->actual -
						   prev->p.axis[a].actual) / T) <=
				    1e-6 * (1 + fabs(f32(x))));
			break;
		default:
			assert_true(f32(x) == (float)s->cmd_v[a]);
			break;
		}
	}
	/* the terms add up to what went to the DAC (far from its limit),
	 * within the rounding the loop carries into the next code (half a
	 * code from this cycle, half from the last: pid.c) */
	if (mask & (1u << SH2000_GS_PID_I))
		assert_true(fabs(P + I + D + FF - pa->dac) <= 1.0 + 1e-3);
}

/*
 * The central property: a motion recorded from 20 samples before its start
 * equals, sample for sample, what the firmware computed in those cycles.
 */
static void equals_internals(void **state)
{
	struct harness *h = *state;
	const uint16_t m0 = (1u << SH2000_GATHER_SIGNALS) - 1u;
	const uint16_t m1 = (1u << SH2000_GS_SETPOINT) | (1u << SH2000_GS_DAC) |
			    (1u << SH2000_GS_ENCODER);
	struct rec r;
	unsigned int n = move(1e6), i, start;
	uint32_t rec_no;

	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, m0), SH2000_RES_OK);
	assert_int_equal(gset(h, 1, SH2000_GF_SIGNALS, m1), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 1500), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_TRIGGER,
			      SH2000_GATHER_ON_MOTION), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 20), SH2000_RES_OK);
	watch(h, 10000);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, &rec_no),
			 SH2000_RES_OK);
	h_cycles(h, 100);	/* the ring holds the last 20 of these */
	h_stream(h, (const int32_t (*)[SH2000_AXES])pts, n, 100000);
	h_cycles(h, 1600);
	read_all(h, &r);
	assert_int_equal(r.record, rec_no);
	assert_int_equal(r.values, 13);
	assert_int_equal(r.samples, 1500);
	assert_int_equal(r.trig_index, 20);
	for (start = 0; start < nseen; start++)
		if (seen[start].p.state == SH2000_STATE_RUNNING)
			break;
	assert_true(start > 20 && start < nseen);
	/* the trigger is the first cycle in motion; sample 0 is 20 before */
	assert_int_equal(r.trig_cycle, (uint32_t)seen[start].p.servo_cycle);
	assert_int_equal(r.first_cycle, (uint32_t)seen[start].p.servo_cycle - 20);
	for (i = 0; i < r.samples; i++) {
		const struct seen *s = at_cycle(r.first_cycle + i);
		const struct seen *prev = at_cycle(r.first_cycle + i - 1);

		check_axis(&r.v[i * 13], m0, 0, s, prev);
		check_axis(&r.v[i * 13 + 10], m1, 1, s, prev);
	}
	/* the motion really is in there: axis 0 moved 1e6 counts */
	assert_int_equal((int32_t)r.v[(r.samples - 1) * 13], 1000000);
	free(r.v);
}

/* Every PERIOD cycles; a pre-trigger ring that wrapped keeps the last
 * samples; the fault trigger. */
static void period_and_fault(void **state)
{
	struct harness *h = *state;
	struct rec r;
	unsigned int i;

	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, 1u << SH2000_GS_ENCODER),
			 SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PERIOD, 7), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 50), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 10), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_TRIGGER,
			      SH2000_GATHER_ON_FAULT), SH2000_RES_OK);
	watch(h, 10000);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	h_cycles(h, 500);	/* 71 pre samples: the ring wrapped */
	info(h, &r);
	assert_int_equal(r.state, SH2000_GATHER_ARMED);
	/* a jammed carriage under a set-point that moves: FERR */
	assert_int_equal(sh2000_fw_inject(h->fw, SH2000_INJECT_JAM, 0, 0), 0);
	memset(pts, 0, sizeof(pts[0]));
	pts[0][0] = 30000;
	h_stream(h, (const int32_t (*)[SH2000_AXES])pts, 1, 2000);
	h_cycles(h, 500);
	read_all(h, &r);
	assert_int_equal(r.samples, 50);
	assert_int_equal(r.trig_index, 10);
	assert_int_equal(r.period, 7);
	assert_true(r.trig_cycle > r.first_cycle + 9 * 7 &&
		    r.trig_cycle <= r.first_cycle + 10 * 7);
	for (i = 0; i < r.samples; i++)
		assert_int_equal((int32_t)r.v[i],
				 (int32_t)at_cycle(r.first_cycle + 7 * i)->p.axis[0].actual);
	/* the fault is in the cycle of the trigger */
	assert_int_equal(at_cycle(r.trig_cycle)->p.state != SH2000_STATE_RUNNING, 1);
	assert_int_equal(at_cycle(r.trig_cycle - 1)->p.state, SH2000_STATE_RUNNING);
	free(r.v);
}

/* NOW starts in the arming cycle; STOP ends a record early, and one that
 * never triggered keeps its pre-trigger samples. */
static void now_and_stop(void **state)
{
	struct harness *h = *state;
	struct rec r;
	uint32_t v;

	assert_int_equal(gset(h, 2, SH2000_GF_SIGNALS, 1u << SH2000_GS_DAC),
			 SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 1000), SH2000_RES_OK);
	watch(h, 10000);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	h_cycles(h, 30);
	info(h, &r);
	assert_int_equal(r.state, SH2000_GATHER_RECORDING);
	/* the answer came in the cycle that armed: seen[0]; samples since */
	assert_int_equal(r.first_cycle, (uint32_t)seen[0].p.servo_cycle);
	assert_int_equal(r.trig_index, 0);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_READ, 0, 0, 0, NULL),
			 SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_STOP, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	read_all(h, &r);
	/* the arming cycle, 30 more, one each for INFO and the refused READ;
	 * STOP acts before the sample of its cycle */
	assert_int_equal(r.samples, 33);
	free(r.v);
	/* armed for a motion that never comes, stopped: pre samples only */
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_TRIGGER,
			      SH2000_GATHER_ON_MOTION), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 5), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, &v),
			 SH2000_RES_OK);
	h_cycles(h, 3);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_STOP, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	read_all(h, &r);
	assert_int_equal(r.record, v);
	assert_int_equal(r.trig_index, SH2000_GATHER_NO_TRIGGER);
	assert_int_equal(r.samples, 4);	/* the arming cycle and 3 */
	free(r.v);
}

static void refusals(void **state)
{
	struct harness *h = *state;

	assert_int_equal(gset(h, 0, SH2000_GATHER_FIELDS, 0), SH2000_RES_BAD_PARAM);
	assert_int_equal(gset(h, 4, SH2000_GF_SIGNALS, 1), SH2000_RES_BAD_AXIS);
	assert_int_equal(gset(h, 0, SH2000_GF_PERIOD, 1), SH2000_RES_BAD_AXIS);
	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, 1u << SH2000_GATHER_SIGNALS),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PERIOD, 0), SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PERIOD, 65536), SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 0), SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_TRIGGER, 3), SH2000_RES_BAD_VALUE);
	/* no signal chosen */
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_BAD_VALUE);
	/* more than the memory holds: 3 values x 11000 samples */
	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, 7), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 11000), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 10000), SH2000_RES_OK);
	/* a pre-trigger needs a trigger to come */
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 10), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_TRIGGER,
			      SH2000_GATHER_ON_MOTION), SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 10000),
			 SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_BAD_VALUE);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_PRETRIGGER, 9999), SH2000_RES_OK);
	/* nothing recorded yet */
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_READ, 0, 0, 0, NULL),
			 SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	/* armed: the configuration and a second record wait */
	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, 1), SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_BUSY);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_STOP, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	assert_int_equal(gset(h, 0, SH2000_GF_SIGNALS, 1), SH2000_RES_OK);
	/* an unknown op in the gathering range */
	assert_int_equal(h_cmd(h, 21, 0, 0, 0, NULL), SH2000_RES_BAD_OP);
}

/* Recording goes on across a reset and an emergency stop; a bit flipped
 * in the window is caught by its check word. */
static void survives_and_checks(void **state)
{
	struct harness *h = *state;
	uint16_t w[SH2000_GATHER_WINDOW_WORDS];
	struct rec r;
	unsigned int n;

	assert_int_equal(gset(h, 1, SH2000_GF_SIGNALS, 1u << SH2000_GS_SETPOINT),
			 SH2000_RES_OK);
	assert_int_equal(gset(h, GLOBAL, SH2000_GF_SAMPLES, 200), SH2000_RES_OK);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_ARM, 0, 0, 0, NULL),
			 SH2000_RES_OK);
	sh2000_dpram_write(h->ram, SH2000_W_ESTOP_REQ, 1);
	h_cycles(h, 50);
	assert_int_equal(h_cmd(h, SH2000_CMD_RESET, 0, 0, 0, NULL), SH2000_RES_OK);
	h_cycles(h, 200);
	read_all(h, &r);
	assert_int_equal(r.samples, 200);
	free(r.v);
	assert_int_equal(h_cmd(h, SH2000_CMD_GATHER_READ, 0, 0, 5, NULL),
			 SH2000_RES_OK);
	n = window(h, SH2000_GATHER_KIND_DATA, w);
	w[SH2000_GW_HEADER + 3] ^= 0x0100;
	assert_int_not_equal(w[SH2000_GW_CHECK], sh2000_gather_check(w, n));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(equals_internals, h_setup_enabled,
						h_teardown),
		cmocka_unit_test_setup_teardown(period_and_fault, h_setup_enabled,
						h_teardown),
		cmocka_unit_test_setup_teardown(now_and_stop, h_setup_enabled,
						h_teardown),
		cmocka_unit_test_setup_teardown(refusals, h_setup, h_teardown),
		cmocka_unit_test_setup_teardown(survives_and_checks,
						h_setup_enabled, h_teardown),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);

	free(seen);
	return r;
}
