// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * hal_sh2000's comp= (hal/comp.c) on the in-process card, no LinuxCNC:
 * a good table file is checked, loaded and shown (its identity, sum and
 * count, the card's status the same); a bad one is refused by the check
 * with the library's FILE:LINE message and the card's tables do not
 * change; "" and "-" are no table.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "hsc.h"

static char path[64];

static void write_file(const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

static void open_card(struct hsc_card *c)
{
	char msg[256];

	if (hsc_open(c, 0, "sim", msg, sizeof(msg)) < 0)
		fail_msg("hsc_open: %s", msg);
}

static void wanted(void **state)
{
	(void)state;
	assert_false(hsc_comp_wanted(NULL));
	assert_false(hsc_comp_wanted(""));
	assert_false(hsc_comp_wanted("-"));
	assert_true(hsc_comp_wanted("mill.comp"));
}

static void good_table(void **state)
{
	struct sh2000_comp_status st;
	struct hsc_card c;
	char msg[512] = "";

	(void)state;
	write_file("id 0x12345678\npitch X\n0 0\n100 0.002\n200 0.001\n");
	open_card(&c);
	assert_int_equal(hsc_comp_check(&c, path, msg, sizeof(msg)), 0);
	/* the check sends nothing */
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	if (hsc_comp_load(&c, path, msg, sizeof(msg)) < 0)
		fail_msg("hsc_comp_load: %s", msg);
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_ACTIVE);
	assert_int_equal(c.comp.id, 0x12345678u);
	assert_int_equal(c.comp.tables, 1);
	assert_int_equal(c.comp.sum, st.sum);
	assert_int_not_equal(c.comp.sum, 0);
	hsc_close(&c);
}

static void bad_table(void **state)
{
	struct sh2000_comp_status st;
	struct hsc_card c;
	char msg[512] = "", want[128];

	(void)state;
	/* line 5: positions not increasing */
	write_file("id 0x1\npitch X\n0 0\n100 0.002\n50 0.001\n");
	open_card(&c);
	assert_true(hsc_comp_check(&c, path, msg, sizeof(msg)) < 0);
	snprintf(want, sizeof(want), "%s:5:", path);
	if (!strstr(msg, want))
		fail_msg("check's message '%s' lacks '%s'", msg, want);
	/* the loader refuses it the same way, and nothing changes */
	msg[0] = '\0';
	assert_true(hsc_comp_load(&c, path, msg, sizeof(msg)) < 0);
	if (!strstr(msg, want))
		fail_msg("load's message '%s' lacks '%s'", msg, want);
	assert_int_equal(sh2000_comp_status(c.h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	assert_int_equal(c.comp.sum, 0);
	/* a file that is not there: said */
	assert_true(hsc_comp_check(&c, "/nonexistent/mill.comp", msg,
				   sizeof(msg)) < 0);
	assert_non_null(strstr(msg, "/nonexistent/mill.comp"));
	hsc_close(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(wanted),
		cmocka_unit_test(good_table),
		cmocka_unit_test(bad_table),
	};
	int fd, r;

	snprintf(path, sizeof(path), "/tmp/test_hsc_comp_XXXXXX");
	fd = mkstemp(path);
	if (fd < 0)
		return 1;
	close(fd);
	r = cmocka_run_group_tests(tests, NULL, NULL);
	unlink(path);
	return r;
}
