/* SPDX-License-Identifier: MIT */
/*
 * The first-fault record on the host side (protocol 1.4), against a
 * scripted card (fakecard.c): a poll that finds a fault latched reads the
 * record once and sh2000_status_error() names it; a card before 1.4 is
 * never asked for it and gets the old ranking; a torn record is read
 * again (or left unknown by the real-time poll); a command answered
 * since makes the next poll read it again; sh2000_status_faulted() agrees
 * with sh2000_status_error() on every state and fault.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "fakecard.h"

/* Faults latched in the order "record rejected, then axis 1 at its limit
 * switch": the status words, and the record (unless version < 1.4). */
static struct fakecard *crossed_card(unsigned int version)
{
	struct fakecard *f = fakecard_new();
	uint16_t *r = &f->ram[SH2000_W_FIRST_FAULT];

	fakecard_boot(f);
	f->h.card_version = version;
	f->ram[SH2000_W_VERSION] = (uint16_t)version;
	f->ram[SH2000_W_STATE] = SH2000_STATE_FAULT;
	f->ram[SH2000_W_FAULTS] = SH2000_FAULT_REJECTED | SH2000_FAULT_AXIS;
	f->ram[SH2000_W_REJECT_REASON] = SH2000_REJECT_CHECKSUM;
	f->ram[SH2000_W_REJECT_COUNT] = 1;
	f->ram[SH2000_W_AXIS_FAULTS(1)] = SH2000_AXIS_FAULT_HARD_LIMIT;
	/* the snapshot of cycle 0x1_0005; the fault latched 3 cycles later,
	 * past the 32-bit wrap of the low words */
	f->ram[SH2000_W_SNAP_TIME_LO] = 0x0005;
	f->ram[SH2000_W_SNAP_TIME_HI] = 0x0001;
	if (SH2000_PROTO_VERSION_MINOR(version) >= SH2000_PROTO_MINOR_FIRST_FAULT) {
		r[SH2000_FF_AXIS] = SH2000_AXIS_GLOBAL;
		r[SH2000_FF_CYCLE_LO] = 0x0008;
		r[SH2000_FF_CYCLE_HI] = 0x0001;
		r[SH2000_FF_BIT] = SH2000_FAULT_REJECTED;
		r[SH2000_FF_CHECK] = sh2000_first_fault_check(r);
	}
	return f;
}

/* Data reads of the record's first word in the log. */
static unsigned int record_reads(const struct fakecard *f)
{
	unsigned int i, n = 0;

	for (i = 0; i < f->nlog; i++)
		if (f->log[i].op == FAKE_RD &&
		    f->log[i].addr == SH2000_W_FIRST_FAULT)
			n++;
	return n;
}

/* Port cycles in the log. */
static unsigned int cycles(const struct fakecard *f)
{
	unsigned int c[4];

	fakecard_counts(f, c);
	return c[0] + c[1] + c[2] + c[3];
}

static void test_names_the_first(void **state)
{
	struct fakecard *f = crossed_card(SH2000_PROTO_VERSION);
	struct sh2000_status st;
	unsigned int with, without;

	(void)state;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	fakecard_clear_log(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	without = cycles(f);
	f->h.first.valid = 0;	/* as if the faults had just latched */
	fakecard_clear_log(f);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	with = cycles(f);
	assert_int_equal(record_reads(f), 1);
	/* 785 increments from word 47, 5 reads, 4 increments; back to word
	 * 0 for the next poll is one clear either way */
	assert_int_equal(with - without, 785 + 5 + 4);
	printf("# poll with the first-fault record read: %u port cycles (without: %u)\n",
	       with, without);
	assert_int_equal(st.first_fault.bit, SH2000_FAULT_REJECTED);
	assert_int_equal(st.first_fault.axis, SH2000_AXIS_GLOBAL);
	assert_int_equal(st.first_fault.cycle, 0x10008u);
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), -SH2000_EREJECTED);
	/* the same faults: the record is not read again */
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 1);
	assert_int_equal(st.first_fault.bit, SH2000_FAULT_REJECTED);
	fakecard_free(f);
}

static void test_axis_first(void **state)
{
	struct fakecard *f = crossed_card(SH2000_PROTO_VERSION);
	uint16_t *r = &f->ram[SH2000_W_FIRST_FAULT];
	struct sh2000_status st;

	(void)state;
	/* Y's limit first, then X's: an order of axes would say X */
	f->ram[SH2000_W_FAULTS] = SH2000_FAULT_AXIS;
	f->ram[SH2000_W_AXIS_FAULTS(0)] = SH2000_AXIS_FAULT_COUNTER;
	r[SH2000_FF_AXIS] = 1;
	r[SH2000_FF_BIT] = SH2000_AXIS_FAULT_HARD_LIMIT;
	r[SH2000_FF_CHECK] = sh2000_first_fault_check(r);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), -SH2000_EHARD_LIMIT);
	assert_non_null(strstr(sh2000_last_error(&f->h), "axis y: limit switch"));
	fakecard_free(f);
}

static void test_older_card_ranks(void **state)
{
	struct fakecard *f = crossed_card(0x0103);
	uint16_t *r = &f->ram[SH2000_W_FIRST_FAULT];
	struct sh2000_status st;

	(void)state;
	/* a record-looking block in what is reserved on 1.3 is not read */
	r[SH2000_FF_AXIS] = SH2000_AXIS_GLOBAL;
	r[SH2000_FF_BIT] = SH2000_FAULT_REJECTED;
	r[SH2000_FF_CHECK] = sh2000_first_fault_check(r);
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 0);
	assert_int_equal(st.first_fault.bit, 0);
	/* the 1.3 ranking: axis faults before a rejected record */
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), -SH2000_EHARD_LIMIT);
	fakecard_free(f);
}

static void test_torn_record(void **state)
{
	struct fakecard *f = crossed_card(SH2000_PROTO_VERSION);
	struct sh2000_status st;

	(void)state;
	f->ram[SH2000_W_FIRST_FAULT + SH2000_FF_CHECK] ^= 1;
	/* the blocking poll reads it again, then leaves it unknown */
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), SH2000_POLL_RETRIES);
	assert_int_equal(st.first_fault.bit, 0);
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), -SH2000_EHARD_LIMIT);
	/* the real-time poll reads it once a tick */
	fakecard_clear_log(f);
	assert_int_equal(sh2000_poll_once(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 1);
	assert_int_equal(st.first_fault.bit, 0);
	f->ram[SH2000_W_FIRST_FAULT + SH2000_FF_CHECK] ^= 1;
	assert_int_equal(sh2000_poll_once(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 2);
	assert_int_equal(st.first_fault.bit, SH2000_FAULT_REJECTED);
	fakecard_free(f);
}

static void test_reread_after_command(void **state)
{
	struct fakecard *f = crossed_card(SH2000_PROTO_VERSION);
	uint16_t *r = &f->ram[SH2000_W_FIRST_FAULT];
	struct sh2000_status st;

	(void)state;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 1);
	/* another program's RESET, and a new first fault before our poll */
	f->ram[SH2000_W_CMD_ACK]++;
	r[SH2000_FF_AXIS] = 2;
	r[SH2000_FF_BIT] = SH2000_AXIS_FAULT_FERR;
	r[SH2000_FF_CHECK] = sh2000_first_fault_check(r);
	f->ram[SH2000_W_FAULTS] = SH2000_FAULT_AXIS;
	f->ram[SH2000_W_AXIS_FAULTS(1)] = 0;
	f->ram[SH2000_W_AXIS_FAULTS(2)] = SH2000_AXIS_FAULT_FERR;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 2);
	assert_int_equal(st.first_fault.axis, 2);
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), -SH2000_EFERR);
	/* nothing latched: nothing named, nothing read */
	f->ram[SH2000_W_FAULTS] = 0;
	f->ram[SH2000_W_AXIS_FAULTS(2)] = 0;
	f->ram[SH2000_W_STATE] = SH2000_STATE_IDLE;
	r[SH2000_FF_BIT] = 0;
	assert_int_equal(sh2000_poll_locked(&f->h, &st), 0);
	assert_int_equal(record_reads(f), 2);
	assert_int_equal(st.first_fault.bit, 0);
	assert_int_equal(sh2000_status_error_locked(&f->h, &st), 0);
	fakecard_free(f);
}

/* sh2000_status_faulted() is true exactly when sh2000_status_error()
 * names an error: every card state, every card fault bit, every axis
 * fault bit on every axis. */
static void test_faulted_agrees(void **state)
{
	struct fakecard *f = fakecard_new();
	struct sh2000_status st;
	unsigned int s, b, a;

	(void)state;
	fakecard_boot(f);
	for (s = 0; s <= SH2000_STATE_ESTOP + 1; s++) {
		for (b = 0; b <= 16; b++) {
			memset(&st, 0, sizeof(st));
			st.card_state = s;
			st.card_faults = b < 16 ? 1u << b : 0;
			assert_int_equal(sh2000_status_faulted(&st),
					 sh2000_status_error_locked(&f->h, &st) != 0);
		}
		for (a = 0; a < SH2000_AXES; a++) {
			for (b = 0; b < 16; b++) {
				memset(&st, 0, sizeof(st));
				st.card_state = s;
				st.axis[a].faults = 1u << b;
				assert_true(sh2000_status_faulted(&st));
				assert_int_not_equal(sh2000_status_error_locked(&f->h, &st), 0);
			}
		}
	}
	memset(&st, 0, sizeof(st));
	st.card_state = SH2000_STATE_RUNNING;
	assert_false(sh2000_status_faulted(&st));
	fakecard_free(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_names_the_first),
		cmocka_unit_test(test_axis_first),
		cmocka_unit_test(test_older_card_ranks),
		cmocka_unit_test(test_torn_record),
		cmocka_unit_test(test_reread_after_command),
		cmocka_unit_test(test_faulted_agrees),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
