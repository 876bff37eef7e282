/* SPDX-License-Identifier: MIT */
/*
 * Data gathering through libsh2000 (protocol 1.2): a record read in chunks
 * equals what the card did in every servo cycle (the `sim` card's cycle
 * observer), with the trigger now, on the next motion and on a fault; a
 * part of a record is read alone; a chunk corrupted on the bus is read
 * again, one that stays corrupt is an error; a record replaced by a new one is noticed; bad
 * configurations are refused before anything is sent; a card before 1.2
 * is told apart.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "simtest.h"
#include "sh2000_hw.h"

#define MAXC 20000

static struct sh2000_cycle *cyc;
static unsigned int ncyc;

static void on_cycle(void *arg, const struct sh2000_cycle *c)
{
	(void)arg;
	if (ncyc < MAXC)
		cyc[ncyc++] = *c;
}

/* The observer sees every cycle in order: index by the first one. */
static const struct sh2000_cycle *at_cycle(uint32_t c)
{
	uint32_t i = c - (uint32_t)cyc[0].servo_cycle;

	if (!ncyc || i >= ncyc)
		fail_msg("servo cycle %u not observed", c);
	assert_int_equal((uint32_t)cyc[i].servo_cycle, c);
	return &cyc[i];
}

static void matches_cycles(void **state)
{
	const unsigned int sig = (1u << SH2000_GS_SETPOINT) | (1u << SH2000_GS_ENCODER) |
				 (1u << SH2000_GS_FERR) | (1u << SH2000_GS_DAC);
	struct sh2000 *h = simtest_open();
	struct sh2000_gather_config gc;
	struct sh2000_gather_info gi;
	struct sh2000_port_counters pc0, pc1;
	int32_t p[SH2000_AXES];
	double *v;
	unsigned int i, col[8], ax;
	int rec;

	(void)state;
	cyc = calloc(MAXC, sizeof(*cyc));
	ncyc = 0;
	CHECK(sh2000_watch_cycles(h, on_cycle, NULL));
	CHECK(sh2000_enable(h, 0x3));
	sh2000_gather_config_default(&gc);
	gc.signals[0] = sig;
	gc.signals[1] = 1u << SH2000_GS_SETPOINT;
	gc.samples = 2500;
	gc.period = 5;	/* 1.25 s: the whole 1 s motion and its settling */
	gc.trigger = SH2000_GATHER_ON_MOTION;
	gc.pretrigger = 40;
	rec = sh2000_gather_start(h, &gc);
	CHECK(rec);
	CHECK(sh2000_sleep_ns(h, 30000000));	/* the pre-trigger ring fills */
	simtest_cmd(h, p);
	CHECK(simtest_line(h, p, 0, 200, 500, 32, SH2000_PUSH_END));
	CHECK(sh2000_gather_wait(h, (unsigned int)rec, &gi, 10000));
	assert_int_equal(gi.record, (unsigned int)rec);
	assert_int_equal(gi.samples, 2500);
	assert_int_equal(gi.values, 5);
	assert_int_equal(gi.trigger_index, 40);
	assert_true(fabs(gi.sample_s - 5e-4) < 1e-12);
	for (i = 0; i < gi.values; i++)
		CHECK(sh2000_gather_column(&gi, i, &ax, &col[i]));
	assert_int_equal(col[0], SH2000_GS_SETPOINT);
	assert_int_equal(col[3], SH2000_GS_DAC);
	assert_int_equal(sh2000_gather_column(&gi, 5, &ax, &col[5]), -EINVAL);
	assert_int_equal(ax, 1);	/* the last column found: axis 1's */
	v = calloc((size_t)gi.samples * gi.values, sizeof(*v));
	CHECK(sh2000_port_counters(h, &pc0));
	assert_int_equal(sh2000_gather_read(h, &gi, 0, gi.samples, v), (int)gi.samples);
	CHECK(sh2000_port_counters(h, &pc1));
	print_message("# gather: %u values in %u chunks, %.0f port cycles per chunk\n",
		      gi.samples * gi.values,
		      (gi.samples * gi.values + SH2000_GATHER_CHUNK_VALUES - 1) /
			      SH2000_GATHER_CHUNK_VALUES,
		      (double)(pc1.clears + pc1.increments + pc1.data_reads +
			       pc1.data_writes - pc0.clears - pc0.increments -
			       pc0.data_reads - pc0.data_writes) /
			      ((gi.samples * gi.values + SH2000_GATHER_CHUNK_VALUES - 1) /
			       SH2000_GATHER_CHUNK_VALUES));
	for (i = 0; i < gi.samples; i++) {
		const struct sh2000_cycle *c = at_cycle(gi.first_cycle + 5 * i);
		const double *s = &v[i * 5];

		assert_true(s[0] == nearbyint(c->axis[0].fine_cmd));
		assert_true(s[1] == c->axis[0].actual);
		assert_true(s[2] == (float)(c->axis[0].fine_cmd - c->axis[0].actual));
		assert_true(s[3] == c->axis[0].dac);
		assert_true(s[4] == nearbyint(c->axis[1].fine_cmd));
	}
	/* the motion is in it: 500 * 200 counts */
	assert_true(v[(gi.samples - 1) * 5] - v[0] == 100000.0);
	/* a part of the record: the same values */
	{
		double part[10];

		assert_int_equal(sh2000_gather_read(h, &gi, 1000, 2, part), 2);
		assert_memory_equal(part, &v[1000 * 5], sizeof(part));
		assert_int_equal(sh2000_gather_read(h, &gi, 2499, 2, part), -EINVAL);
	}
	free(v);
	free(cyc);
	sh2000_close(h);
}

/*
 * Trigger on a fault: the emergency stop in the middle of a motion. The
 * trigger's sample is the first after the latch, the pre-trigger samples
 * are the motion before it, and every value is the card's own.
 */
static void fault_trigger(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_gather_config gc;
	struct sh2000_gather_info gi;
	int32_t p[SH2000_AXES];
	double v[2 * 300];
	unsigned int i;
	int rec;

	(void)state;
	cyc = calloc(MAXC, sizeof(*cyc));
	ncyc = 0;
	CHECK(sh2000_watch_cycles(h, on_cycle, NULL));
	CHECK(sh2000_enable(h, 0x1));
	sh2000_gather_config_default(&gc);
	gc.signals[0] = (1u << SH2000_GS_ENCODER) | (1u << SH2000_GS_DAC);
	gc.samples = 300;
	gc.period = 2;
	gc.pretrigger = 100;
	gc.trigger = SH2000_GATHER_ON_FAULT;
	rec = sh2000_gather_start(h, &gc);
	CHECK(rec);
	simtest_cmd(h, p);
	CHECK(simtest_line(h, p, 0, 500, 400, 32, SH2000_PUSH_END));
	for (i = 0; i < 50; i++) {	/* well into the motion, host alive */
		CHECK(sh2000_poll(h, NULL));
		CHECK(sh2000_sleep_ns(h, 2000000));
	}
	CHECK(sh2000_gather_info(h, &gi));
	assert_int_equal(gi.state, SH2000_GATHER_ARMED);	/* a motion is no fault */
	CHECK(sh2000_estop(h, 1000));
	CHECK(sh2000_gather_wait(h, (unsigned int)rec, &gi, 10000));
	assert_int_equal(gi.trigger, SH2000_GATHER_ON_FAULT);
	assert_int_equal(gi.samples, 300);
	assert_int_equal(gi.trigger_index, 100);
	assert_true(gi.trigger_cycle > gi.first_cycle + 99 * 2 &&
		    gi.trigger_cycle <= gi.first_cycle + 100 * 2);
	assert_int_equal(at_cycle(gi.trigger_cycle)->state, SH2000_STATE_ESTOP);
	assert_int_not_equal(at_cycle(gi.trigger_cycle - 1)->state, SH2000_STATE_ESTOP);
	assert_int_equal(sh2000_gather_read(h, &gi, 0, gi.samples, v), 300);
	for (i = 0; i < gi.samples; i++) {
		const struct sh2000_cycle *c = at_cycle(gi.first_cycle + 2 * i);

		assert_true(v[2 * i] == c->axis[0].actual);
		assert_true(v[2 * i + 1] == c->axis[0].dac);
	}
	/* the axis was moving before the stop */
	assert_true(v[2 * 99] - v[0] > 1000.0);
	free(cyc);
	sh2000_close(h);
}

/* ---- a card whose bus flips a bit of the window ---- */

struct flaky {
	struct sh2000_cardsim *c;
	unsigned int counter;
	int flips;		/* reads of the word still to corrupt */
	unsigned int word;
	uint16_t version;	/* 0: as the card says */
};

static void f_out(void *ctx, unsigned int reg, uint16_t v)
{
	struct flaky *f = ctx;

	if (reg == SH2000_REG_ADDR_CLEAR)
		f->counter = 0;
	else if (reg == SH2000_REG_ADDR_INC)
		f->counter = (f->counter + 1) % SH2000_RAM_WORDS;
	sh2000_cardsim_out(f->c, reg, v);
}

static uint16_t f_in(void *ctx, unsigned int reg)
{
	struct flaky *f = ctx;
	uint16_t v = sh2000_cardsim_in(f->c, reg);

	if (reg != SH2000_REG_DATA)
		return v;
	if (f->counter == SH2000_W_VERSION && f->version)
		return f->version;
	if (f->counter == f->word && f->flips) {
		if (f->flips > 0)
			f->flips--;
		v ^= 0x0040;
	}
	return v;
}

static uint64_t f_now(void *ctx)
{
	return sh2000_cardsim_now_ns(((struct flaky *)ctx)->c);
}

static void f_advance(void *ctx, uint64_t ns)
{
	sh2000_cardsim_advance(((struct flaky *)ctx)->c, ns);
}

static void f_close(void *ctx)
{
	struct flaky *f = ctx;

	sh2000_cardsim_destroy(f->c);
	free(f);
}

static struct sh2000 *flaky_open(struct flaky **out, uint16_t version)
{
	struct sh2000_ports p = {
		.size = sizeof(p),
		.flags = SH2000_PORTS_F_VIRTUAL_TIME,
		.out = f_out, .in = f_in, .now_ns = f_now,
		.advance_ns = f_advance, .close = f_close,
	};
	struct flaky *f = calloc(1, sizeof(*f));
	struct sh2000 *h = NULL;
	char msg[256];

	assert_int_equal(sh2000_cardsim_create(&f->c, NULL), 0);
	f->version = version;
	p.ctx = f;
	if (sh2000_open_ports(&h, &p, "flaky", msg, sizeof(msg)) < 0)
		fail_msg("open: %s", msg);
	*out = f;
	return h;
}

/* A short record of the encoder, DONE. */
static int record_now(struct sh2000 *h, struct sh2000_gather_info *gi,
		      uint32_t samples)
{
	struct sh2000_gather_config gc;
	int rec;

	sh2000_gather_config_default(&gc);
	gc.signals[2] = 1u << SH2000_GS_ENCODER;
	gc.samples = samples;
	rec = sh2000_gather_start(h, &gc);
	if (rec < 0)
		return rec;
	return sh2000_gather_wait(h, (unsigned int)rec, gi, 1000);
}

static void flipped_chunks(void **state)
{
	struct flaky *f;
	struct sh2000 *h = flaky_open(&f, 0);
	struct sh2000_gather_info gi;
	double v[300], again[300];

	(void)state;
	CHECK(record_now(h, &gi, 300));
	CHECK(sh2000_gather_read(h, &gi, 0, 300, v));
	/* one flip in a payload word: that chunk is read again, same values */
	f->word = SH2000_W_GATHER_BASE + SH2000_GW_HEADER + 7;
	f->flips = 1;
	CHECK(sh2000_gather_read(h, &gi, 0, 300, again));
	assert_int_equal(f->flips, 0);
	assert_memory_equal(v, again, sizeof(v));
	/* a word that is always wrong: an error naming the values */
	f->flips = -1;
	assert_int_equal(sh2000_gather_read(h, &gi, 0, 300, again),
			 -SH2000_EGATHER_CHECK);
	assert_non_null(strstr(sh2000_last_error(h), "values 0..59"));
	/* the header's sequence word counts too */
	f->word = SH2000_W_GATHER_BASE + SH2000_GW_SEQ;
	assert_int_equal(sh2000_gather_read(h, &gi, 120, 1, again),
			 -SH2000_EGATHER_CHECK);
	f->flips = 0;
	CHECK(sh2000_gather_read(h, &gi, 120, 1, again));
	assert_true(again[0] == v[120]);
	sh2000_close(h);
}

static void replaced(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_gather_info one, two;
	double v[10];

	(void)state;
	CHECK(record_now(h, &one, 100));
	CHECK(record_now(h, &two, 100));
	assert_int_equal(two.record, (one.record + 1) & 0xffff);
	assert_int_equal(sh2000_gather_read(h, &one, 0, 10, v), -SH2000_EGATHER_LOST);
	assert_non_null(strstr(sh2000_last_error(h), "replaced"));
	assert_int_equal(sh2000_gather_wait(h, one.record, &two, 100),
			 -SH2000_EGATHER_LOST);
	CHECK(sh2000_gather_read(h, &two, 0, 10, v));
	sh2000_close(h);
}

static void refusals(void **state)
{
	struct sh2000 *h = simtest_open();
	struct sh2000_gather_config gc;
	struct sh2000_gather_info before, after;
	struct flaky *f;
	struct sh2000 *old;

	(void)state;
	CHECK(sh2000_gather_info(h, &before));
	assert_int_equal(before.state, SH2000_GATHER_OFF);
	assert_int_equal(before.buffer, SH2000_GATHER_BUFFER_VALUES);
	sh2000_gather_config_default(&gc);
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "no signal"));
	gc.signals[1] = 1u << SH2000_GATHER_SIGNALS;
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "axis 1"));
	gc.signals[1] = 0x3ff;
	gc.samples = 32768 / 10 + 1;
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	gc.samples = 100;
	gc.period = 0;
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	gc.period = 1;
	gc.pretrigger = 5;
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	assert_non_null(strstr(sh2000_last_error(h), "pre-trigger"));
	gc.trigger = 3;
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_EPARAM);
	/* none of that reached the card */
	CHECK(sh2000_gather_info(h, &after));
	assert_memory_equal(after.signals, before.signals, sizeof(before.signals));
	assert_int_equal(after.capacity, before.capacity);
	/* armed for a motion: a second start waits for a stop */
	gc.trigger = SH2000_GATHER_ON_MOTION;
	CHECK(sh2000_gather_start(h, &gc));
	assert_int_equal(sh2000_gather_start(h, &gc), -SH2000_ECMD_BUSY);
	assert_int_equal(sh2000_gather_wait(h, after.record + 1, &after, 50),
			 -SH2000_ETIMEOUT);
	CHECK(sh2000_gather_stop(h));
	CHECK(sh2000_gather_start(h, &gc));
	sh2000_close(h);
	/* a 1.1 card: told apart, with its version in the message */
	old = flaky_open(&f, 0x0101);
	assert_int_equal(sh2000_gather_info(old, &after), -EOPNOTSUPP);
	assert_non_null(strstr(sh2000_last_error(old), "1.1"));
	assert_int_equal(sh2000_gather_start(old, &gc), -EOPNOTSUPP);
	sh2000_close(old);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(matches_cycles),
		cmocka_unit_test(fault_trigger),
		cmocka_unit_test(flipped_chunks),
		cmocka_unit_test(replaced),
		cmocka_unit_test(refusals),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
