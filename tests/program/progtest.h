/* SPDX-License-Identifier: MIT */
/* Helpers for the program reader tests: read a text, look at the result. */
#ifndef SH2000_PROGTEST_H
#define SH2000_PROGTEST_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sh2000/program.h"

static struct sh2000_program P;
static struct sh2000_prog_diags D;

static inline int setup(void **state)
{
	(void)state;
	sh2000_program_init(&P);
	sh2000_prog_diags_init(&D);
	return 0;
}

static inline int teardown(void **state)
{
	(void)state;
	sh2000_program_free(&P);
	sh2000_prog_diags_free(&D);
	return 0;
}

/* Read text as fmt, named like a file of that format. */
static inline int rd_opt(enum sh2000_prog_format fmt, const char *text,
		  const struct sh2000_prog_options *opt)
{
	static const char *const names[] = {
		"t.txt", "t.ngc", "t.canon", "t.csv", "t.json",
	};

	sh2000_prog_diags_free(&D);
	sh2000_prog_diags_init(&D);
	return sh2000_program_read(&P, fmt, names[fmt], text, strlen(text),
				   opt, &D);
}

static inline int rd(enum sh2000_prog_format fmt, const char *text)
{
	return rd_opt(fmt, text, NULL);
}

/* Print the diagnostics (for failing tests). */
static inline void dump(void)
{
	char buf[512];

	for (size_t i = 0; i < D.count; i++) {
		sh2000_prog_diag_format(&D.items[i], buf, sizeof(buf));
		fprintf(stderr, "  %s\n", buf);
	}
}

static inline const struct sh2000_prog_diag *first_error(void)
{
	for (size_t i = 0; i < D.count; i++)
		if (D.items[i].severity == SH2000_PROG_ERROR)
			return &D.items[i];
	return NULL;
}

/* Reading fails with a first error of this code at line:col; nothing is
 * left to move. */
#define expect_error(fmt, text, code, line, col) \
	expect_error_at(__LINE__, fmt, text, code, line, col)
static inline void expect_error_at(int at, enum sh2000_prog_format fmt,
			    const char *text, enum sh2000_prog_diag_code code,
			    unsigned int line, unsigned int col)
{
	int ret = rd(fmt, text);
	const struct sh2000_prog_diag *e = first_error();

	if (ret != -SH2000_PROG_EINVALID || !e || e->code != code ||
	    e->pos.line != line || e->pos.column != col) {
		fprintf(stderr, "test line %d: ret %d, want code %d at %u:%u for:\n%s\n",
			at, ret, code, line, col, text);
		dump();
	}
	assert_int_equal(ret, -SH2000_PROG_EINVALID);
	assert_non_null(e);
	assert_int_equal(e->code, code);
	assert_int_equal(e->pos.line, line);
	assert_int_equal(e->pos.column, col);
	assert_int_equal(P.count, 0);
}

#define expect_ok(fmt, text) expect_ok_at(__LINE__, fmt, text, NULL)
#define expect_ok_opt(fmt, text, opt) expect_ok_at(__LINE__, fmt, text, opt)
static inline void expect_ok_at(int at, enum sh2000_prog_format fmt, const char *text,
			 const struct sh2000_prog_options *opt)
{
	int ret = rd_opt(fmt, text, opt);

	if (ret != 0) {
		fprintf(stderr, "test line %d: ret %d for:\n%s\n", at, ret, text);
		dump();
	}
	assert_int_equal(ret, 0);
	assert_int_equal(D.errors, 0);
}

static inline size_t count_kind(enum sh2000_prog_kind k)
{
	size_t n = 0;

	for (size_t i = 0; i < P.count; i++)
		n += P.blocks[i].kind == k;
	return n;
}

/* The idx-th block of kind k. */
static inline const struct sh2000_prog_block *nth(enum sh2000_prog_kind k, size_t idx)
{
	for (size_t i = 0; i < P.count; i++)
		if (P.blocks[i].kind == k && idx-- == 0)
			return &P.blocks[i];
	fail_msg("no block %s #%zu", sh2000_prog_kind_name(k), idx);
	return NULL;
}

static inline size_t count_warnings(enum sh2000_prog_diag_code code)
{
	size_t n = 0;

	for (size_t i = 0; i < D.count; i++)
		n += D.items[i].severity == SH2000_PROG_WARNING &&
		     D.items[i].code == code;
	return n;
}

static inline bool has_message(const char *needle)
{
	for (size_t i = 0; i < D.count; i++)
		if (strstr(D.items[i].message, needle))
			return true;
	return false;
}

#define assert_near(a, b, eps) do { \
	double a_ = (a), b_ = (b); \
	if (!(fabs(a_ - b_) <= (eps))) \
		fail_msg("%s = %.9g, expected %.9g", #a, a_, b_); \
} while (0)

static inline void assert_pos4(const double *p, double x, double y, double z, double a)
{
	assert_near(p[0], x, 1e-9);
	assert_near(p[1], y, 1e-9);
	assert_near(p[2], z, 1e-9);
	assert_near(p[3], a, 1e-9);
}

#define G SH2000_PROG_GCODE
#define CANON SH2000_PROG_CANON
#define CSV SH2000_PROG_CSV
#define JSON SH2000_PROG_NURBS_JSON

#endif
