/* SPDX-License-Identifier: MIT */
/*
 * The index latch a host arms while the card runs (protocol 1.6) on the
 * host side, against a scripted card (fakecard.c): a card that reports
 * 1.4 or 1.5 is refused by every sh2000_index_* call, with a message
 * naming its version and the one needed, and without a port cycle (no
 * command reaches a card that would answer it as unknown); a 1.6 card
 * gets the command (AXIS, flags, the travel in counts) and its answer.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "fakecard.h"

static struct fakecard *card(unsigned int version)
{
	struct fakecard *f = fakecard_new();

	fakecard_boot(f);
	f->h.card_version = version;
	f->ram[SH2000_W_VERSION] = (uint16_t)version;
	f->h.scale[0] = 100000.0;
	fakecard_clear_log(f);
	return f;
}

static void refused(unsigned int version, const char *named)
{
	struct fakecard *f = card(version);
	struct sh2000_status st;
	struct sh2000_index ix;
	unsigned int c[4];

	memset(&st, 0, sizeof(st));
	assert_int_equal(sh2000_index_supported(&f->h), -EOPNOTSUPP);
	assert_int_equal(sh2000_index_arm(&f->h, 0, SH2000_INDEX_F_MASK, 2.0),
			 -EOPNOTSUPP);
	/* the message names the card's version and the one needed */
	assert_non_null(strstr(sh2000_last_error(&f->h), named));
	assert_non_null(strstr(sh2000_last_error(&f->h), "needs 1.6"));
	assert_int_equal(sh2000_index_disarm(&f->h, 0), -EOPNOTSUPP);
	assert_int_equal(sh2000_index_read(&f->h, 0, &st, &ix), -EOPNOTSUPP);
	/* nothing reached the card */
	fakecard_counts(f, c);
	assert_int_equal(c[0] + c[1] + c[2] + c[3], 0);
	fakecard_free(f);
}

static void test_refuses_1_5(void **state)
{
	(void)state;
	refused(0x0105, "protocol 1.5");
}

static void test_refuses_1_4(void **state)
{
	(void)state;
	refused(0x0104, "protocol 1.4");
}

static void test_arms_on_1_6(void **state)
{
	struct fakecard *f = card(SH2000_PROTO_VERSION);

	(void)state;
	assert_true(SH2000_PROTO_VERSION_MINOR(SH2000_PROTO_VERSION) >=
		    SH2000_PROTO_MINOR_INDEX);
	f->auto_ack = 1;
	f->ack_result = SH2000_RES_OK;
	f->ack_value = 7;
	assert_int_equal(sh2000_index_supported(&f->h), 0);
	/* the card's number of the arm back; the command as the card sees
	 * it: axis, flags, 2.5 mm of travel in counts */
	assert_int_equal(sh2000_index_arm(&f->h, 0, SH2000_INDEX_F_MASK, 2.5), 7);
	assert_int_equal(f->ram[SH2000_W_CMD_OP], SH2000_CMD_INDEX_ARM);
	assert_int_equal(f->ram[SH2000_W_CMD_AXIS], 0);
	assert_int_equal(f->ram[SH2000_W_CMD_PARAM], SH2000_INDEX_F_MASK);
	assert_int_equal((uint32_t)f->ram[SH2000_W_CMD_ARG_LO] |
			 ((uint32_t)f->ram[SH2000_W_CMD_ARG_HI] << 16), 250000u);
	/* a travel that is not 32-bit counts is the caller's error */
	assert_int_equal(sh2000_index_arm(&f->h, 0, 0, 1e9), -EINVAL);
	assert_int_equal(sh2000_index_arm(&f->h, SH2000_AXES, 0, 0), -EINVAL);
	fakecard_free(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_refuses_1_5),
		cmocka_unit_test(test_refuses_1_4),
		cmocka_unit_test(test_arms_on_1_6),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
