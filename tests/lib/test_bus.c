/* SPDX-License-Identifier: MIT */
/*
 * The register-level bus, status, command and estop paths against a
 * scripted card (fakecard.c), cycle by cycle: the bus issues exactly the
 * port-cycle sequence the kernel driver's rule gives (sh2000_core.c: seek
 * each word with sh2000_seek_plan() unless already there, then the data
 * cycle), and the documented costs of a poll, a push and a command.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "fakecard.h"

/* The driver's rule, word by word, as a reference. */
static unsigned int driver_rule(unsigned int pos, unsigned int addr,
				unsigned int n, int write,
				struct fake_event *ev)
{
	unsigned int k = 0, w, i;

	for (w = addr; w < addr + n; w++) {
		if (pos != w) {
			struct sh2000_seek s = sh2000_seek_plan(pos, w);

			if (s.clear) {
				ev[k].op = FAKE_CLEAR;
				ev[k++].addr = 0;
				pos = 0;
			}
			for (i = 0; i < s.increments; i++) {
				pos = (pos + 1) & SH2000_ADDR_MASK;
				ev[k].op = FAKE_INC;
				ev[k++].addr = (uint16_t)pos;
			}
		}
		ev[k].op = write ? FAKE_WR : FAKE_RD;
		ev[k++].addr = (uint16_t)w;
	}
	return k;
}

static uint32_t lcg(uint32_t *s)
{
	*s = *s * 1664525u + 1013904223u;
	return *s >> 8;
}

static void test_stream_equals_driver_rule(void **state)
{
	static struct fake_event ref[4096];
	struct fakecard *f = fakecard_new();
	uint16_t buf[SH2000_RAM_WORDS], shadow[SH2000_RAM_WORDS];
	uint32_t seed = 12345;
	unsigned int t, i;

	(void)state;
	memset(shadow, 0, sizeof(shadow));
	for (t = 0; t < 5000; t++) {
		unsigned int addr = lcg(&seed) % SH2000_RAM_WORDS;
		unsigned int max = SH2000_RAM_WORDS - addr;
		unsigned int n = 1 + lcg(&seed) % (max < 80 ? max : 80);
		int write = lcg(&seed) & 1;
		unsigned int pos = f->h.bus.pos, k;

		/* the driver starts where the bus believes the counter is */
		if (pos != SH2000_SEEK_UNKNOWN)
			assert_int_equal(pos, f->counter);
		k = driver_rule(pos, addr, n, write, ref);
		fakecard_clear_log(f);
		if (write) {
			for (i = 0; i < n; i++)
				buf[i] = shadow[addr + i] = (uint16_t)lcg(&seed);
			assert_int_equal(sh2000_wr(&f->h, addr, n, buf), 0);
		} else {
			assert_int_equal(sh2000_rd(&f->h, addr, n, buf), 0);
			assert_memory_equal(buf, &shadow[addr], 2 * n);
		}
		assert_int_equal(f->nlog, k);
		for (i = 0; i < k; i++) {
			assert_int_equal(f->log[i].op, ref[i].op);
			if (ref[i].op != FAKE_CLEAR)
				assert_int_equal(f->log[i].addr, ref[i].addr);
		}
		/* lazy: the counter stays on the last word */
		assert_int_equal(f->h.bus.pos, addr + n - 1);
	}
	assert_memory_equal(f->ram, shadow, sizeof(shadow));
	fakecard_free(f);
}

static void test_seek_costs(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_port_counters c;
	uint16_t w;

	(void)state;
	/* unknown position: clear + target increments */
	sh2000_rd(&f->h, 10, 1, &w);
	sh2000_port_counters(&f->h, &c);
	assert_int_equal(c.clears, 1);
	assert_int_equal(c.increments, 10);
	/* through the wrap: 1023 -> 3 is 4 increments, a tie with clear + 3:
	 * the tie keeps the counter */
	f->h.bus.pos = 1023;
	f->counter = 1023;
	sh2000_rd(&f->h, 3, 1, &w);
	sh2000_port_counters(&f->h, &c);
	assert_int_equal(c.clears, 1);
	assert_int_equal(c.increments, 14);
	/* 1000 -> 5: clear + 5 beats 29 increments */
	f->h.bus.pos = 1000;
	f->counter = 1000;
	sh2000_rd(&f->h, 5, 1, &w);
	sh2000_port_counters(&f->h, &c);
	assert_int_equal(c.clears, 2);
	assert_int_equal(c.increments, 19);
	/* backwards: clear + target */
	sh2000_rd(&f->h, 3, 1, &w);
	sh2000_port_counters(&f->h, &c);
	assert_int_equal(c.clears, 3);
	assert_int_equal(c.increments, 22);
	/* a streamed word costs 2 cycles, the first word after a seek 1 */
	sh2000_rd(&f->h, 3, 100, (uint16_t[100]){ 0 });
	sh2000_port_counters(&f->h, &c);
	assert_int_equal(c.increments, 22 + 99);
	assert_int_equal(c.data_reads, 4 + 100);
	fakecard_free(f);
}

static unsigned int cycles(const struct fakecard *f)
{
	return f->nlog;
}

static void test_poll_cost(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	unsigned int c[4];

	(void)state;
	fakecard_boot(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	fakecard_counts(f, c);
	/* clear, 47 reads with 46 increments, 1 increment, heartbeat write */
	assert_int_equal(c[FAKE_CLEAR], 1);
	assert_int_equal(c[FAKE_INC], 47);
	assert_int_equal(c[FAKE_RD], SH2000_STATUS_WORDS);
	assert_int_equal(c[FAKE_WR], 1);
	assert_int_equal(cycles(f), 96);
	assert_int_equal(f->ram[SH2000_W_HOST_HEARTBEAT], f->h.host_hb);
	/* steady state: the counter sits on 47, word 0 is one clear away */
	fakecard_clear_log(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(cycles(f), 96);
	fakecard_free(f);
}

static void test_push_cost(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	int32_t pts[SH2000_RING_RECORDS][SH2000_AXES];
	unsigned int one, two, full;

	(void)state;
	memset(pts, 0, sizeof(pts));
	fakecard_boot(f);
	sh2000_poll_locked(&f->h, &st);
	fakecard_clear_log(f);
	assert_int_equal(sh2000_push_counts(&f->h, pts, 1, 0), 1);
	one = cycles(f);
	/* check 3..7 (4+9), seek to the ring (57), one record (12 data +
	 * 11 increments), publish 47..48 (48 + 3) */
	assert_int_equal(one, 4 + 9 + 57 + 23 + 48 + 3);
	assert_int_equal(f->ram[SH2000_W_HEAD], 1);
	/* each further record of a batch costs 24 cycles */
	f->ram[SH2000_W_TAIL] = 1;	/* card consumed it */
	fakecard_clear_log(f);
	assert_int_equal(sh2000_push_counts(&f->h, pts, 2, 0), 2);
	two = cycles(f);
	assert_int_equal(two, one + 24 + 12);	/* +12: slot 1 is 12 further */
	/* a full ring's batch */
	f->ram[SH2000_W_TAIL] = 3;
	fakecard_clear_log(f);
	assert_int_equal(sh2000_push_counts(&f->h, pts, SH2000_RING_RECORDS, 0),
			 SH2000_RING_RECORDS);
	full = cycles(f);
	print_message("push: 1 record %u cycles, 64 records %u (%.2f/record)\n",
		      one, full, full / 64.0);
	assert_true(full < 26 * SH2000_RING_RECORDS + 200);
	/* and now no room: nothing written */
	fakecard_clear_log(f);
	assert_int_equal(sh2000_push_counts(&f->h, pts, 1, 0),
			 -SH2000_EQUEUE_FULL);
	{
		unsigned int c[4];

		fakecard_counts(f, c);
		assert_int_equal(c[FAKE_WR], 0);
	}
	/* batches larger than the ring are refused outright */
	assert_int_equal(sh2000_push_counts(&f->h, pts, SH2000_RING_RECORDS + 1, 0),
			 -EMSGSIZE);
	fakecard_free(f);
}

/*
 * The point mailbox (protocol 1.3): a real-time tick's point goes into
 * words 57..63 right after a poll, 24 cycles; the ring where the card has
 * not taken everything yet, and always on a card below 1.3.
 */
static void test_post_cost(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	int32_t pts[1][SH2000_AXES] = { { 1000, -2000, 0x12345678, -5 } };
	int32_t p[SH2000_AXES] = { 1100, -2100, 0x12345678 + 500000, -5 };
	const uint16_t *m = &f->ram[SH2000_W_MBOX];
	unsigned int a;

	(void)state;
	fakecard_boot(f);
	f->h.card_version = SH2000_PROTO_VERSION;
	f->ram[SH2000_W_STATE] = SH2000_STATE_RUNNING;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	/* the first record goes through the ring: positions whole */
	assert_int_equal(sh2000_push_point(&f->h, pts[0], 0), 1);
	assert_int_equal(f->ram[SH2000_W_HEAD], 1);
	f->ram[SH2000_W_POSTED] = 1;	/* the card received it */
	f->ram[SH2000_W_MBOX + SH2000_MBOX_SEQ] = 0xffff;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	fakecard_clear_log(f);
	assert_int_equal(sh2000_push_point(&f->h, p, 0), 1);
	/* 9 increments to POSTED, read, increment, 7 writes, 6 increments */
	assert_int_equal(cycles(f), 24);
	assert_int_equal(m[SH2000_MBOX_SEQ], 1);
	assert_int_equal(m[SH2000_MBOX_CHECK], sh2000_mbox_check(m));
	for (a = 0; a < SH2000_AXES; a++)
		assert_int_equal(sh2000_mbox_position(m, a, pts[0][a]), p[a]);
	assert_int_equal(f->ram[SH2000_W_HEAD], 1);	/* not the ring's */
	/* the card has not taken it yet: the next point through the ring,
	 * its number after the post's */
	p[0] += 100;
	assert_int_equal(sh2000_push_point(&f->h, p, 0), 1);
	assert_int_equal(f->ram[SH2000_W_HEAD], 3);
	assert_int_equal(f->ram[SH2000_W_RING_BASE + 2 * SH2000_RECORD_WORDS +
				SH2000_REC_SEQ], 2);
	assert_int_equal(m[SH2000_MBOX_SEQ], 1);
	/* a step beyond 20 bits: the ring */
	f->ram[SH2000_W_POSTED] = 3;
	p[1] -= SH2000_MBOX_STEP_MAX + 1;
	assert_int_equal(sh2000_push_point(&f->h, p, 0), 1);
	assert_int_equal(f->ram[SH2000_W_HEAD], 4);
	/* a card below 1.3: the ring, whatever POSTED says */
	f->h.card_version = (SH2000_PROTO_MAJOR << 8) | 1u;
	f->ram[SH2000_W_POSTED] = 4;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	fakecard_clear_log(f);
	p[0] += 100;
	assert_int_equal(sh2000_push_point(&f->h, p, 0), 1);
	assert_int_equal(f->ram[SH2000_W_HEAD], 5);
	assert_true(cycles(f) > 100);
	assert_int_equal(m[SH2000_MBOX_SEQ], 1);
	fakecard_free(f);
}

static void test_record_format(void **state)
{
	struct fakecard *f = fakecard_new();
	const int32_t pts[2][SH2000_AXES] = { { 1, -2, 0x12345678, -0x7fffffff },
					       { 5, 6, 7, 8 } };
	const uint16_t *r;

	(void)state;
	fakecard_boot(f);
	f->h.head = 63;		/* the batch wraps from slot 63 to slot 0 */
	f->h.segments = 1000;
	f->ram[SH2000_W_TAIL] = 63;
	assert_int_equal(sh2000_push_counts(&f->h, pts, 2, SH2000_PUSH_END), 2);
	r = &f->ram[SH2000_W_RING_BASE + 63 * SH2000_RECORD_WORDS];
	assert_int_equal(sh2000_w32(&r[SH2000_REC_POS_LO(2)]), 0x12345678);
	assert_int_equal(sh2000_w32(&r[SH2000_REC_POS_LO(3)]), -0x7fffffff);
	assert_int_equal(r[SH2000_REC_SEQ], 1000);
	assert_int_equal(r[SH2000_REC_FLAGS], 0);
	assert_int_equal(r[SH2000_REC_CHECK], sh2000_record_check(r));
	r = &f->ram[SH2000_W_RING_BASE];
	assert_int_equal(sh2000_w32(&r[SH2000_REC_POS_LO(0)]), 5);
	assert_int_equal(r[SH2000_REC_SEQ], 1001);
	assert_int_equal(r[SH2000_REC_FLAGS], SH2000_REC_F_END);
	assert_int_equal(r[SH2000_REC_CHECK], sh2000_record_check(r));
	assert_int_equal(f->ram[SH2000_W_HEAD], 65);
	fakecard_free(f);
}

static void test_command_cost_and_results(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	int32_t v = 0;
	unsigned int res;

	(void)state;
	fakecard_boot(f);
	sh2000_poll_locked(&f->h, &st);
	fakecard_clear_log(f);
	f->ack_value = 0xdeadbeef;
	assert_int_equal(sh2000_command_locked(&f->h, SH2000_CMD_GET_PARAM, 1,
					       SH2000_P_KP, 0, &v, 100), 0);
	assert_int_equal((uint32_t)v, 0xdeadbeef);
	/* 49..55 from 47 (2 + 13), answer 8..11 (9 + 7) */
	assert_int_equal(cycles(f), 31);
	assert_int_equal(f->ram[SH2000_W_CMD_CHECK],
			 sh2000_cmd_check(f->ram[SH2000_W_CMD_SEQ],
					  SH2000_CMD_GET_PARAM, 1, SH2000_P_KP,
					  0, 0));
	for (res = 1; res <= SH2000_RES_DISABLED + 1; res++) {
		int want = res <= SH2000_RES_DISABLED ?
			   -(SH2000_ECMD_OP + (int)res - 1) : -SH2000_ECMD_UNKNOWN;

		f->ack_result = (uint16_t)res;
		assert_int_equal(sh2000_command_locked(&f->h, SH2000_CMD_NOP, 0,
						       0, 0, NULL, 100), want);
		assert_non_null(strstr(f->h.err, "nop"));
	}
	/* answered while the host was descheduled for 150 ms right after
	 * looking at the old ACK: its last look, past the time limit, sees
	 * the answer; not a timeout */
	f->ack_result = SH2000_RES_OK;
	f->late_ack_ns = 150000000ull;
	assert_int_equal(sh2000_command_locked(&f->h, SH2000_CMD_NOP, 0, 0, 0,
					       NULL, 100), 0);
	f->late_ack_ns = 0;
	/* the card's process descheduled for 150 ms right after the command
	 * (heartbeat limit 200 ms): it had no chance within the host's
	 * 100 ms; its answer in its first cycle after is not a timeout */
	f->h.hb.limit_ns = 200000000ull;
	f->stall_ns = 150000000ull;
	assert_int_equal(sh2000_command_locked(&f->h, SH2000_CMD_NOP, 0, 0, 0,
					       NULL, 100), 0);
	assert_true(f->now_ns >= f->stalled_until);
	f->stall_ns = 0;
	/* no answer: a timeout, after 100 ms of (fake) time */
	f->auto_ack = 0;
	assert_int_equal(sh2000_command_locked(&f->h, SH2000_CMD_NOP, 0, 0, 0,
					       NULL, 100), -SH2000_ETIMEOUT);
	fakecard_free(f);
}

static void test_estop_cost(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;

	(void)state;
	fakecard_boot(f);
	sh2000_poll_locked(&f->h, &st);
	fakecard_clear_log(f);
	assert_int_equal(sh2000_estop(&f->h, 10), 0);
	/* clear + write word 0 come first: nothing before them */
	assert_int_equal(f->log[0].op, FAKE_CLEAR);
	assert_int_equal(f->log[1].op, FAKE_WR);
	assert_int_equal(f->log[1].addr, SH2000_W_ESTOP_REQ);
	/* then 4 increments, the ESTOP_ACK read, 1 increment, the STATE
	 * read (acknowledged and stopped) */
	assert_int_equal(cycles(f), 9);
	/* the card's process descheduled for 150 ms right after the request
	 * (heartbeat limit 200 ms): acknowledged in its first cycle after,
	 * not a timeout of the host's 100 ms */
	f->h.hb.limit_ns = 200000000ull;
	f->stall_ns = 150000000ull;
	f->ram[SH2000_W_STATE] = SH2000_STATE_IDLE;
	assert_int_equal(sh2000_estop(&f->h, 100), 0);
	assert_true(f->now_ns >= f->stalled_until);
	fakecard_free(f);
}

static void test_torn_snapshot(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;

	(void)state;
	fakecard_boot(f);
	f->tear_polls = 3;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(st.retries, 3);
	f->tear_polls = 1000;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), -SH2000_ETORN);
	fakecard_free(f);
}

/* A card whose heartbeat stands still while its snapshot stays torn
 * inside one publication stopped in the middle of it (a served model
 * killed while it wrote): a stopped card, EHEARTBEAT at the heartbeat
 * limit. One that resumes before the limit was only stalled. */
static void test_torn_stopped(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	uint64_t t0;

	(void)state;
	fakecard_boot(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	f->hb_running = 0;
	f->tear_polls = 100;		/* about 5 ms inside one publication */
	t0 = f->now_ns;
	if (sh2000_poll_locked(&f->h, &st))
		fail_msg("%s (%.3f ms)", sh2000_last_error(&f->h),
			 (f->now_ns - t0) / 1e6);
	assert_int_equal(st.retries, 100);
	assert_true(f->now_ns - t0 > SH2000_HEARTBEAT_LIMIT_NS / 10);
	f->tear_polls = 100000;		/* and now for good */
	t0 = f->now_ns;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), -SH2000_EHEARTBEAT);
	assert_non_null(strstr(sh2000_last_error(&f->h), "left torn"));
	/* the heartbeat was last seen to move at the first poll */
	assert_true(st.heartbeat_age_ns >= SH2000_HEARTBEAT_LIMIT_NS);
	assert_true(f->now_ns - t0 < SH2000_HEARTBEAT_LIMIT_NS);
	fakecard_free(f);
}

/* A card that goes on publishing while a slow reader tears every read
 * (each read inside another publication) is alive: the poll keeps
 * reading past a tenth of the heartbeat limit, which is for a card
 * stuck inside one publication, and gives up only after 1024 such reads.
 * (A reader in a loaded VM, 8 programs on one vCPU, gave up after 16.8 ms
 * of such reads.) */
static void test_torn_moving(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	uint64_t t0;

	(void)state;
	fakecard_boot(f);
	f->tear_moving = 1;
	f->tear_polls = 80;		/* about 7 ms of reads */
	t0 = f->now_ns;
	if (sh2000_poll_locked(&f->h, &st))
		fail_msg("%s (%.3f ms, limit %.3f ms)", sh2000_last_error(&f->h),
			 (f->now_ns - t0) / 1e6, f->h.hb.limit_ns / 1e6);
	assert_int_equal(st.retries, 80);
	assert_true(f->now_ns - t0 > SH2000_HEARTBEAT_LIMIT_NS / 10);
	f->tear_polls = 100000;		/* a reader that never catches one */
	assert_int_equal(sh2000_poll_locked(&f->h, &st), -SH2000_ETORN);
	/* the immediate re-reads, then 1024 torn reads of new publications
	 * (status.c's TORN_MOVING_READS), then the read that gives up */
	assert_int_equal(f->tear_polls, 100000 - SH2000_POLL_RETRIES - 1024 - 1);
	fakecard_free(f);
}

static void test_heartbeat_loss(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	uint64_t t0;

	(void)state;
	fakecard_boot(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	f->hb_running = 0;
	t0 = f->now_ns;
	while (sh2000_poll_locked(&f->h, &st) == 0)
		f->now_ns += 500000;
	assert_true(f->now_ns - t0 >= SH2000_HEARTBEAT_LIMIT_NS);
	assert_true(f->now_ns - t0 <= SH2000_HEARTBEAT_LIMIT_NS + 1000000);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), -SH2000_EHEARTBEAT);
	assert_non_null(strstr(f->h.err, "heartbeat stuck"));
	f->hb_running = 1;
	f->ram[SH2000_W_HEARTBEAT]++;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	fakecard_free(f);
}

static void set32(uint16_t *ram, unsigned int w, uint32_t v)
{
	ram[w] = (uint16_t)v;
	ram[w + 1] = (uint16_t)(v >> 16);
}

static void test_counter_extension(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	unsigned int act = SH2000_W_SNAP_AXIS(1) + SH2000_SNAP_ACT_LO;
	unsigned int cmd = SH2000_W_SNAP_AXIS(1) + SH2000_SNAP_CMD_LO;

	(void)state;
	fakecard_boot(f);
	set32(f->ram, act, 0x0ffffff0u);	/* -16 as 28 bits */
	set32(f->ram, cmd, (uint32_t)-10);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(st.axis[1].pos_counts, -16);
	assert_int_equal(st.axis[1].ferr_counts, 6);
	/* upward through 2^27 several times: the 64-bit value keeps going */
	{
		int64_t want = -16;
		unsigned int i;

		for (i = 0; i < 40; i++) {
			want += 50000000;
			set32(f->ram, act, (uint32_t)want & 0x0fffffffu);
			set32(f->ram, cmd, (uint32_t)(int32_t)want);
			assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
			assert_true(st.axis[1].pos_counts == want);
			assert_int_equal(st.axis[1].ferr_counts,
					 (int32_t)(want - (int64_t)(int32_t)want) == 0 ?
					 0 : st.axis[1].ferr_counts);
		}
		assert_true(st.axis[1].pos_counts > (1ll << 30));
		assert_true(st.axis[1].pos_mm > 1e6);
	}
	fakecard_free(f);
}

static void test_fault_errors(void **state)
{
	static const struct {
		unsigned int state, faults, axis_faults;
		int code;
	} cases[] = {
		{ SH2000_STATE_ESTOP, SH2000_FAULT_ESTOP, 0, -SH2000_EESTOP },
		{ SH2000_STATE_FAULT, SH2000_FAULT_UNDERRUN, 0, -SH2000_EUNDERRUN },
		{ SH2000_STATE_FAULT, SH2000_FAULT_HOST_TIMEOUT, 0, -SH2000_EHOST_TIMEOUT },
		{ SH2000_STATE_FAULT, SH2000_FAULT_REJECTED, 0, -SH2000_EREJECTED },
		{ SH2000_STATE_FAULT, SH2000_FAULT_PROTOCOL, 0, -SH2000_EPROTOCOL },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_FERR, -SH2000_EFERR },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_SOFT_LIMIT, -SH2000_ESOFT_LIMIT },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_HARD_LIMIT, -SH2000_EHARD_LIMIT },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_DAC_SAT, -SH2000_EDAC_SAT },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_COUNTER, -SH2000_ECOUNTER },
		{ SH2000_STATE_FAULT, SH2000_FAULT_AXIS, SH2000_AXIS_FAULT_HOME, -SH2000_EHOME },
		{ SH2000_STATE_FAULT, 0, 0, -SH2000_EFAULTED },
		/* refused for "not ready" after an underrun: the cause wins */
		{ SH2000_STATE_FAULT, SH2000_FAULT_REJECTED | SH2000_FAULT_UNDERRUN,
		  0xffff, -SH2000_EUNDERRUN },
	};
	int32_t pts[1][SH2000_AXES] = { { 0 } };
	unsigned int i;

	(void)state;
	for (i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct fakecard *f = fakecard_new();
		unsigned int c[4];

		fakecard_boot(f);
		f->ram[SH2000_W_STATE] = (uint16_t)cases[i].state;
		f->ram[SH2000_W_FAULTS] = (uint16_t)cases[i].faults;
		f->ram[SH2000_W_REJECT_SEQ] = 77;
		f->ram[SH2000_W_REJECT_REASON] = SH2000_REJECT_VELOCITY;
		if (cases[i].axis_faults == 0xffff)
			f->ram[SH2000_W_REJECT_REASON] = SH2000_REJECT_STATE;
		else
			f->ram[SH2000_W_AXIS_FAULTS(2)] =
				(uint16_t)cases[i].axis_faults;
		f->h.segments = 100;
		assert_int_equal(sh2000_push_counts(&f->h, pts, 1, 0), cases[i].code);
		fakecard_counts(f, c);
		assert_int_equal(f->ram[SH2000_W_HEAD], 0);	/* nothing published */
		assert_int_equal(sh2000_wait_idle(&f->h, 10), cases[i].code);
		if (cases[i].axis_faults && cases[i].axis_faults != 0xffff)
			assert_non_null(strstr(f->h.err, "axis z: "));
		if (cases[i].code == -SH2000_EREJECTED)
			assert_non_null(strstr(f->h.err, "segment 77"));
		fakecard_free(f);
	}
}

/* What the library's port-cycle costs rely on in the protocol's layout. */
static void test_layout(void **state)
{
	(void)state;
	/* estop: clear + write from anywhere */
	assert_int_equal(SH2000_W_ESTOP_REQ, 0);
	/* a poll streams 0..46 and the host heartbeat is the next word */
	assert_int_equal(SH2000_W_HOST_HEARTBEAT, SH2000_STATUS_WORDS);
	/* push: HOST_HEARTBEAT and HEAD published in one 2-word stream */
	assert_int_equal(SH2000_W_HEAD, SH2000_W_HOST_HEARTBEAT + 1);
	/* push check: HEARTBEAT..TAIL in one 5-word read */
	assert_int_equal(SH2000_W_HEARTBEAT + 1, SH2000_W_ESTOP_ACK);
	assert_int_equal(SH2000_W_ESTOP_ACK + 1, SH2000_W_STATE);
	assert_int_equal(SH2000_W_STATE + 1, SH2000_W_FAULTS);
	assert_int_equal(SH2000_W_FAULTS + 1, SH2000_W_TAIL);
	/* command: OP..SEQ one upward stream with SEQ last; the answer
	 * ACK..VALUE_HI one read with ACK first */
	assert_int_equal(SH2000_W_CMD_AXIS, SH2000_W_CMD_OP + 1);
	assert_int_equal(SH2000_W_CMD_PARAM, SH2000_W_CMD_OP + 2);
	assert_int_equal(SH2000_W_CMD_ARG_LO, SH2000_W_CMD_OP + 3);
	assert_int_equal(SH2000_W_CMD_ARG_HI, SH2000_W_CMD_OP + 4);
	assert_int_equal(SH2000_W_CMD_CHECK, SH2000_W_CMD_OP + 5);
	assert_int_equal(SH2000_W_CMD_SEQ, SH2000_W_CMD_OP + 6);
	assert_int_equal(SH2000_W_CMD_RESULT, SH2000_W_CMD_ACK + 1);
	assert_int_equal(SH2000_W_CMD_VALUE_LO, SH2000_W_CMD_ACK + 2);
	assert_int_equal(SH2000_W_CMD_VALUE_HI, SH2000_W_CMD_ACK + 3);
	/* snapshot read upwards: END, body, BEGIN, BEGIN the last status word */
	assert_true(SH2000_W_SNAP_SEQ_END < SH2000_W_SNAP_AXIS(0));
	assert_true(SH2000_W_SNAP_TIME_HI < SH2000_W_SNAP_SEQ_BEGIN);
	assert_int_equal(SH2000_W_SNAP_SEQ_BEGIN, SH2000_STATUS_WORDS - 1);
	/* ring: inside the RAM, slots of whole records, 16-bit counters */
	assert_true(SH2000_W_RING_BASE > SH2000_W_CMD_SEQ);
	assert_true(SH2000_W_RING_END <= SH2000_RAM_WORDS);
	assert_int_equal(65536 % SH2000_RING_RECORDS, 0);
	assert_int_equal(SH2000_REC_CHECK, SH2000_RECORD_WORDS - 1);
}

static void test_strerror(void **state)
{
	int e;

	(void)state;
	for (e = SH2000_E_BASE; e <= SH2000_E_LAST; e++) {
		const char *s = sh2000_strerror(-e);

		assert_non_null(s);
		/* holes in the range are unused codes */
		if (strncmp(s, "unknown", 7))
			assert_true(strlen(s) > 5);
	}
	assert_string_equal(sh2000_strerror(-SH2000_EVERSION),
			    "card speaks another protocol version");
	assert_string_equal(sh2000_strerror(-ENOENT), "No such file or directory");
	assert_string_equal(sh2000_strerror(0), "success");
	assert_string_equal(sh2000_strerror(-99999), "unknown error");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_stream_equals_driver_rule),
		cmocka_unit_test(test_seek_costs),
		cmocka_unit_test(test_poll_cost),
		cmocka_unit_test(test_push_cost),
		cmocka_unit_test(test_post_cost),
		cmocka_unit_test(test_record_format),
		cmocka_unit_test(test_command_cost_and_results),
		cmocka_unit_test(test_estop_cost),
		cmocka_unit_test(test_torn_snapshot),
		cmocka_unit_test(test_torn_moving),
		cmocka_unit_test(test_torn_stopped),
		cmocka_unit_test(test_heartbeat_loss),
		cmocka_unit_test(test_counter_extension),
		cmocka_unit_test(test_fault_errors),
		cmocka_unit_test(test_layout),
		cmocka_unit_test(test_strerror),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
