// SPDX-License-Identifier: MIT
/*
 * A card older than protocol 1.5 has no compensation tables: the library
 * says so (naming both versions) before it writes a word.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "fakecard.h"

static void refused_before_anything(void **state)
{
	static const uint16_t img[SH2000_COMP_HEADER_WORDS] = {
		SH2000_COMP_MAGIC, SH2000_COMP_FORMAT, 0, 0, 0, 0 };
	struct fakecard *f = fakecard_new();
	struct sh2000_comp_status st;
	unsigned int c[4];

	(void)state;
	fakecard_boot(f);
	f->h.card_version = (1u << 8) | 4u;
	f->ram[SH2000_W_VERSION] = (uint16_t)f->h.card_version;
	fakecard_clear_log(f);
	assert_int_equal(sh2000_comp_load_image(&f->h, img, SH2000_COMP_HEADER_WORDS,
						NULL), -EOPNOTSUPP);
	assert_non_null(strstr(sh2000_last_error(&f->h), "protocol 1.4"));
	assert_non_null(strstr(sh2000_last_error(&f->h), "need 1.5"));
	assert_int_equal(sh2000_comp_clear(&f->h), -EOPNOTSUPP);
	assert_int_equal(sh2000_comp_status(&f->h, &st), -EOPNOTSUPP);
	fakecard_counts(f, c);
	assert_int_equal(c[3], 0);	/* no data written */
	fakecard_free(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(refused_before_anything),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
