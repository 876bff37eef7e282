/* SPDX-License-Identifier: MIT */
/*
 * Every reader on mangled input (a fixed pseudo-random sequence, so runs
 * repeat): it either reads the text or reports at least one error with a
 * position and leaves nothing to move; what it reads is finite. Run under
 * the sanitizers this is the readers' memory-safety check.
 */
#include <stdlib.h>

#include "progtest.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;

static uint32_t next(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (uint32_t)(rng >> 16);
}

static const char *const seeds[] = {
	/* G */
	"G21 G90 G17 F300\nG0 X10 Y0\nG3 X0 Y10 I-10 J0\nG2 J-10 P2\n"
	"G3 X10 Y0 Z-5 J-10\nG18 G2 X20 Z0 R10\nG19 G3 Y5 Z5 J5\nS100 M3 M8\n"
	"G4 P0.5\nM1\nG17 G90\nG5.2 P1 L4\nX0 Y1 P1\nX2 Y2 P1\nX2 Y0 P2\nG5.3\nG20 G91 G1 X1 A1\nM2\n",
	/* CANON */
	"    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
	"   16 N10    SET_FEED_RATE(600.0000)\n"
	"   17 N20    STRAIGHT_TRAVERSE(10.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)\n"
	"   18 N30    STRAIGHT_FEED(10.0000, 0.0000, 0.0000, 1.0000, 0.0000, 0.0000)\n"
	"   19 N40    ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 1, -2.0000, 1.0000, 0.0000, 0.0000)\n"
	"   20 N50    DWELL(0.5000)\n   21 N60    COMMENT(\"a, (b)\")\n   24 N70    PROGRAM_END()\n",
	/* CSV */
	"# x,y\nx, y, z, f\n0, 0, 5, 600\n0, 0, 0,\n50, 0, 0,\n50, 30, 0, 1200\n0, 30, 0,\n",
	/* JSON */
	"{\"feed\": 2, \"curves\": [\n"
	" {\"degree\": 2, \"knots\": [0,0,0,0.3,1,1,1], \"weights\": [1,2,1,1],"
	" \"points\": [[0,0],[10,0,1],[10,10,2,3],[0,10]]},\n"
	" {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[5,0],[5,5]], \"feed\": 4}]}\n",
};
static const enum sh2000_prog_format fmts[] = { G, CANON, CSV, JSON };

static void check(enum sh2000_prog_format fmt, const char *text, size_t len)
{
	int ret;

	sh2000_prog_diags_free(&D);
	sh2000_prog_diags_init(&D);
	ret = sh2000_program_read(&P, fmt, "fuzz", text, len, NULL, &D);
	assert_true(ret == 0 || ret == -SH2000_PROG_EINVALID);
	if (ret) {
		const struct sh2000_prog_diag *e = first_error();

		assert_non_null(e);
		assert_int_equal(P.count, 0);
		assert_non_null(e->message);
		return;
	}
	assert_int_equal(D.errors, 0);
	for (size_t i = 0; i < P.count; i++) {
		const struct sh2000_prog_block *b = &P.blocks[i];

		assert_true(b->pos.line >= 1);
		for (int a = 0; a < 4; a++)
			assert_true(isfinite(b->start[a]) && isfinite(b->end[a]));
		assert_true(isfinite(b->feed) && b->feed >= 0);
		if (b->kind == SH2000_PROG_ARC)
			assert_true(isfinite(b->u.arc.sweep) && b->u.arc.r0 > 0);
		if (b->kind == SH2000_PROG_LINE || b->kind == SH2000_PROG_ARC ||
		    b->kind == SH2000_PROG_NURBS)
			assert_true(b->feed > 0);
	}
}

static void test_mangled(void **state)
{
	static const char alphabet[] = "GMXYZAIJKRPLFNST0123456789.-+ ()[];#%/\n\",:{}e";
	char buf[1024];

	(void)state;
	for (size_t s = 0; s < sizeof(seeds) / sizeof(seeds[0]); s++) {
		size_t n0 = strlen(seeds[s]);

		check(fmts[s], seeds[s], n0);
		assert_int_equal(D.errors, 0);
		for (int round = 0; round < 3000; round++) {
			size_t n = n0;
			int edits = 1 + (int)(next() % 4);

			memcpy(buf, seeds[s], n);
			for (int e = 0; e < edits && n > 0; e++) {
				size_t at = next() % n;
				uint32_t op = next() % 4;

				if (op == 0) {			/* replace */
					buf[at] = alphabet[next() % (sizeof(alphabet) - 1)];
				} else if (op == 1 && n > 1) {	/* delete */
					memmove(buf + at, buf + at + 1, n - at - 1);
					n--;
				} else if (op == 2 && n + 1 < sizeof(buf)) {	/* insert */
					memmove(buf + at + 1, buf + at, n - at);
					buf[at] = alphabet[next() % (sizeof(alphabet) - 1)];
					n++;
				} else {			/* cut short */
					n = at;
				}
			}
			/* not NUL-terminated: the readers take a length */
			check(fmts[s], buf, n);
		}
	}
}

static void test_random_bytes(void **state)
{
	char buf[512];

	(void)state;
	for (int round = 0; round < 2000; round++) {
		size_t n = next() % sizeof(buf);

		for (size_t i = 0; i < n; i++)
			buf[i] = (char)(next() & 0xff);
		check(fmts[round % 4], buf, n);
	}
	check(G, "", 0);
	check(CANON, "", 0);
	check(CSV, "", 0);
	check(JSON, "", 0);
}

/* A NUL inside a line is refused where it is, in every format: read as
 * the end of a number it would turn "0.\0\0001" into 0 (for a G64 P, no
 * tolerance at all) and the program would run something else. */
static void test_nul_byte(void **state)
{
	static const struct {
		enum sh2000_prog_format fmt;
		const char *name, *text;
		size_t len;
		unsigned int col;
	} cases[] = {
#define TEXT(s) s, sizeof(s) - 1
		{ SH2000_PROG_GCODE, "t.ngc", TEXT("G64 P0.\0\0001\nG1 X1 F100\n"), 8 },
		{ SH2000_PROG_CANON, "t.canon",
		  TEXT("SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.\0\0001)\n"), 45 },
		{ SH2000_PROG_CSV, "t.csv", TEXT("x,y\n1,2\0\n"), 4 },
#undef TEXT
	};

	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		const struct sh2000_prog_diag *e;

		sh2000_prog_diags_free(&D);
		sh2000_prog_diags_init(&D);
		assert_int_equal(sh2000_program_read(&P, cases[i].fmt,
						     cases[i].name, cases[i].text,
						     cases[i].len, NULL, &D),
				 -SH2000_PROG_EINVALID);
		e = first_error();
		assert_non_null(e);
		assert_int_equal(e->code, SH2000_PD_SYNTAX);
		assert_int_equal(e->pos.column, cases[i].col);
		assert_non_null(strstr(e->message, "NUL"));
		assert_int_equal(P.count, 0);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_mangled, setup, teardown),
		cmocka_unit_test_setup_teardown(test_random_bytes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_nul_byte, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
