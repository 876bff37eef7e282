// SPDX-License-Identifier: MIT
/* The card in virtual time: port cycles cost 1 us, servo cycles run as
 * time crosses them, emergency-stop latency through the ports,
 * determinism. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include <math.h>

#include "sh2000/sh2000_cardsim.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000_fpga.h"
#include "sh2000_hw.h"

static void seek(struct sh2000_cardsim *c, unsigned int w)
{
	sh2000_cardsim_out(c, SH2000_REG_ADDR_CLEAR, 0);
	while (w--)
		sh2000_cardsim_out(c, SH2000_REG_ADDR_INC, 0);
}

static uint16_t rd(struct sh2000_cardsim *c, unsigned int w)
{
	seek(c, w);
	return sh2000_cardsim_in(c, SH2000_REG_DATA);
}

static void time_flows(void **state)
{
	struct sh2000_cardsim *c;
	uint64_t n[4];
	(void)state;
	assert_int_equal(sh2000_cardsim_create(&c, NULL), 0);
	assert_int_equal(rd(c, SH2000_W_MAGIC), SH2000_PROTO_MAGIC);
	assert_int_equal(rd(c, SH2000_W_VERSION), SH2000_PROTO_VERSION);
	assert_int_equal(rd(c, SH2000_W_HEARTBEAT), 0);
	/* 3 + 4 + 5 port cycles of 1 us */
	assert_int_equal(sh2000_cardsim_now_ns(c), 12000);
	sh2000_cardsim_advance(c, 100000 - 12000 - 1000);
	/* this read happens at 99 us; the first servo cycle runs at 100 us */
	assert_int_equal(sh2000_cardsim_in(c, SH2000_REG_DATA), 0);
	assert_int_equal(sh2000_cardsim_in(c, SH2000_REG_DATA), 1);
	sh2000_cardsim_advance(c, 1000000000ull);
	assert_int_equal(rd(c, SH2000_W_HEARTBEAT), 10001);
	sh2000_cardsim_counters(c, n);
	assert_int_equal(n[0], 4);
	assert_int_equal(n[1], 1 + 2 + 3 + 3);
	assert_int_equal(n[2], 6);
	assert_int_equal(n[3], 0);
	assert_int_equal(sh2000_cardsim_ram(c)[SH2000_W_MAGIC], SH2000_PROTO_MAGIC);
	sh2000_cardsim_destroy(c);
}

static void estop_latency(void **state)
{
	struct sh2000_cardsim *c;
	uint64_t t0, worst = 0;
	unsigned int k;

	(void)state;
	assert_int_equal(sh2000_cardsim_create(&c, NULL), 0);
	for (k = 1; k <= 50; k++) {
		/* request at varying phases of the servo cycle */
		sh2000_cardsim_advance(c, 7777);
		sh2000_cardsim_out(c, SH2000_REG_ADDR_CLEAR, 0);
		t0 = sh2000_cardsim_now_ns(c);
		sh2000_cardsim_out(c, SH2000_REG_DATA, (uint16_t)k);
		seek(c, SH2000_W_ESTOP_ACK);
		while (sh2000_cardsim_in(c, SH2000_REG_DATA) != k)
			;
		if (sh2000_cardsim_now_ns(c) - t0 > worst)
			worst = sh2000_cardsim_now_ns(c) - t0;
	}
	printf("# estop request -> ack through the ports: worst %.0f us (servo period 100 us)\n",
	       worst / 1000.0);
	/* at most one servo period plus the port cycles to see the ack */
	assert_true(worst <= 100000 + 8 * SH2000_PORT_CYCLE_NS);
	sh2000_cardsim_destroy(c);
}

static void deterministic(void **state)
{
	struct sh2000_cardsim *a, *b;
	struct timespec t0, t1;
	double wall;

	(void)state;
	assert_int_equal(sh2000_cardsim_create(&a, NULL), 0);
	assert_int_equal(sh2000_cardsim_create(&b, NULL), 0);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	sh2000_cardsim_advance(a, 60ull * 1000000000ull);
	clock_gettime(CLOCK_MONOTONIC, &t1);
	sh2000_cardsim_advance(b, 30ull * 1000000000ull);
	sh2000_cardsim_advance(b, 30ull * 1000000000ull);
	assert_memory_equal(sh2000_cardsim_ram(a), sh2000_cardsim_ram(b),
			    2 * SH2000_RAM_WORDS);
	wall = (double)(t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
	printf("# 60 s of card time (600000 servo cycles, idle) in %.3f s wall\n", wall);
	sh2000_cardsim_destroy(a);
	sh2000_cardsim_destroy(b);
}

/* What the card did with each axis over the minute, cycle by cycle. */
struct motion_seen {
	double lo[SH2000_AXES], hi[SH2000_AXES];	/* encoder range */
	double last[SH2000_AXES];	/* set-point the cycle before */
	int dir[SH2000_AXES];		/* its direction then (0: none yet) */
	unsigned int turns[SH2000_AXES];	/* reversals of the set-point */
	uint64_t cycles;
};

static void watch_motion(void *ctx, const struct sh2000_probe *p)
{
	struct motion_seen *m = ctx;
	unsigned int a;

	m->cycles++;
	for (a = 0; a < SH2000_AXES; a++) {
		double d = p->axis[a].fine_cmd - m->last[a];
		int dir = d > 0.5 ? 1 : d < -0.5 ? -1 : 0;

		m->lo[a] = fmin(m->lo[a], p->axis[a].actual);
		m->hi[a] = fmax(m->hi[a], p->axis[a].actual);
		if (dir && m->dir[a] && dir != m->dir[a])
			m->turns[a]++;
		if (dir)
			m->dir[a] = dir;
		m->last[a] = p->axis[a].fine_cmd;
	}
}

static void enable_all(struct sh2000_cardsim *c, uint16_t *ram)
{
	sh2000_dpram_write(ram, SH2000_W_CMD_OP, SH2000_CMD_ENABLE);
	sh2000_dpram_write(ram, SH2000_W_CMD_ARG_LO, 0xf);
	sh2000_dpram_write(ram, SH2000_W_CMD_CHECK,
			   sh2000_cmd_check(1, SH2000_CMD_ENABLE, 0, 0, 0xf, 0));
	sh2000_dpram_write(ram, SH2000_W_CMD_SEQ, 1);
	sh2000_cardsim_advance(c, 1000000);
	assert_int_equal(ram[SH2000_W_CMD_RESULT], SH2000_RES_OK);
}

/* Axis a is commanded x / (a + 1): the card did that, stroke after
 * stroke, and consumed a record every coarse period of its minute. */
static void assert_motion(const struct motion_seen *m, uint16_t *ram,
			  uint16_t head, unsigned int turns, double stroke)
{
	uint16_t tail = sh2000_dpram_read(ram, SH2000_W_TAIL);
	unsigned int a, consumed = tail;

	/* 60 s of 2 ms coarse periods, none skipped, none run dry */
	printf("# %u records consumed, %u queued; %u reversals commanded\n",
	       consumed, (uint16_t)(head - tail), turns);
	assert_true(consumed >= 30000 - 1 && consumed <= 30000 + 1);
	assert_true((uint16_t)(head - tail) <= 32);
	assert_int_equal(m->cycles, 600000);
	for (a = 0; a < SH2000_AXES; a++) {
		double end = stroke / (a + 1);

		printf("# axis %u: %.0f .. %.0f counts (commanded 0 .. %.0f), %u reversals\n",
		       a, m->lo[a], m->hi[a], end, m->turns[a]);
		/* the whole stroke, within a count per thousand */
		assert_true(fabs(m->lo[a]) <= end * 1e-3);
		assert_true(fabs(m->hi[a] - end) <= end * 1e-3);
		/* every reversal the card has reached (the last records
		 * queued may hold one more) */
		assert_true(m->turns[a] + 1 >= turns && m->turns[a] <= turns);
	}
}

/* A minute of motion: 100 mm strokes at 300 mm/s, the ring topped up every
 * millisecond straight through the RAM (no port cycles, so this measures
 * the card model alone). */
static void minute_of_motion(void **state)
{
	struct sh2000_cardsim *c;
	struct motion_seen seen = { .cycles = 0 };	/* all at 0 counts */
	uint16_t *ram, head = 0, seq = 1, hb = 0;
	struct timespec t0, t1;
	double x = 0.0, dir = 1.0, v = 0.0, wall;
	const double vmax = 3e7, amax = 3e8, Tc = 0.002, stroke = 1e7;
	unsigned int ms, turns = 0;

	(void)state;
	assert_int_equal(sh2000_cardsim_create(&c, NULL), 0);
	ram = sh2000_cardsim_ram(c);
	enable_all(c, ram);
	sh2000_fw_set_observer(sh2000_cardsim_fw(c), watch_motion, &seen);
	/* the records are counted from here */
	assert_int_equal(sh2000_dpram_read(ram, SH2000_W_TAIL), 0);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (ms = 0; ms < 60000; ms++) {
		while ((uint16_t)(head - sh2000_dpram_read(ram, SH2000_W_TAIL)) < 32) {
			uint16_t rec[SH2000_RECORD_WORDS] = { 0 };
			double left = dir > 0 ? stroke - x : x;
			unsigned int a, i, base;

			/* trapezoid by velocity: brake in time for the stroke end */
			v = fmin(fmin(v + amax * Tc, vmax), sqrt(2 * amax * fmax(left, 0)));
			x += dir * v * Tc;
			if (left - v * Tc <= 0) {
				x = dir > 0 ? stroke : 0;
				dir = -dir;
				v = 0;
				turns++;
			}
			for (a = 0; a < SH2000_AXES; a++) {
				int32_t p = (int32_t)lrint(x / (a + 1));

				rec[SH2000_REC_POS_LO(a)] = (uint16_t)(uint32_t)p;
				rec[SH2000_REC_POS_HI(a)] = (uint16_t)((uint32_t)p >> 16);
			}
			rec[SH2000_REC_SEQ] = seq++;
			rec[SH2000_REC_CHECK] = sh2000_record_check(rec);
			base = SH2000_W_RING_BASE + (head % SH2000_RING_RECORDS) * SH2000_RECORD_WORDS;
			for (i = 0; i < SH2000_RECORD_WORDS; i++)
				sh2000_dpram_write(ram, base + i, rec[i]);
			sh2000_dpram_write(ram, SH2000_W_HEAD, ++head);
		}
		sh2000_dpram_write(ram, SH2000_W_HOST_HEARTBEAT, ++hb);
		sh2000_cardsim_advance(c, 1000000);
	}
	clock_gettime(CLOCK_MONOTONIC, &t1);
	wall = (double)(t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
	assert_int_equal(ram[SH2000_W_FAULTS], 0);
	assert_int_equal(ram[SH2000_W_STATE], SH2000_STATE_RUNNING);
	assert_motion(&seen, ram, head, turns, stroke);
	printf("# 60 s of 4-axis motion (%u records, 600000 servo cycles) in %.3f s wall: %.0fx real time\n",
	       seq - 1u, wall, 60.0 / wall);
	sh2000_cardsim_destroy(c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(time_flows),
		cmocka_unit_test(estop_latency),
		cmocka_unit_test(deterministic),
		cmocka_unit_test(minute_of_motion),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
