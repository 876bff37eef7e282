/* SPDX-License-Identifier: MIT */
/*
 * Tools in programs: LinuxCNC tool tables (good lines, bad lines at
 * FILE:LINE:COLUMN, units), T and M6 (checked, reported once or a pause),
 * and the tool length offsets G43 H, G43, G43.1, G43.2 and G49 applied to
 * the path by the G-code reader and, from rs274's USE_TOOL_LENGTH_OFFSET,
 * by the canonical reader. The numbers are LinuxCNC 2.9's: its rs274 was
 * run on each case while this was written.
 */
#include <errno.h>
#include <stdlib.h>
#include <unistd.h>

#include "progtest.h"

static struct sh2000_tool_table T;

static const char table_text[] =
	"; tool  pocket  offsets  diameter\n"
	"T1 P1 Z+10.0 D6.0 ;6 mm end mill  \r\n"
	"\n"
	"t2 p2 x0.5 z-1 a2 i10 j20 q3 B0 C0\n"
	"   T3   P7\tZ25.4;\n";

static int tab_setup(void **state)
{
	setup(state);
	sh2000_tool_table_init(&T);
	return sh2000_tool_table_read(&T, "t.tbl", table_text,
				      strlen(table_text), &D);
}

static int tab_teardown(void **state)
{
	sh2000_tool_table_free(&T);
	return teardown(state);
}

/* The G-code text read with the table, and tool changes paused at when
 * pause. */
static int rd_tools(enum sh2000_prog_format fmt, const char *text,
		    bool pause)
{
	struct sh2000_prog_options o;

	sh2000_prog_options_default(&o);
	o.tools = &T;
	o.pause_at_tool_change = pause;
	return rd_opt(fmt, text, &o);
}

#define expect_tools_ok(fmt, text, pause) do { \
	int r_ = rd_tools(fmt, text, pause); \
	if (r_) \
		dump(); \
	assert_int_equal(r_, 0); \
} while (0)

/* With the table: the first error has this code at line:col. */
#define expect_tools_error(text, code, line, col) \
	tools_error_at(__LINE__, text, code, line, col)
static void tools_error_at(int at, const char *text,
			   enum sh2000_prog_diag_code code, unsigned int line,
			   unsigned int col)
{
	const struct sh2000_prog_diag *e;

	assert_int_equal(rd_tools(G, text, false), -SH2000_PROG_EINVALID);
	e = first_error();
	assert_non_null(e);
	if (e->code != code || e->pos.line != line || e->pos.column != col) {
		fprintf(stderr, "test line %d: want code %d at %u:%u for:\n%s\n",
			at, code, line, col, text);
		dump();
	}
	assert_int_equal(e->code, code);
	assert_int_equal(e->pos.line, line);
	assert_int_equal(e->pos.column, col);
	assert_int_equal(P.count, 0);
}

static void test_table_good(void **state)
{
	const struct sh2000_tool *t;

	(void)state;
	assert_int_equal(D.errors, 0);
	assert_int_equal(T.count, 3);
	t = sh2000_tool_table_find(&T, 1);
	assert_non_null(t);
	assert_int_equal(t->pocket, 1);
	assert_near(t->offset[SH2000_PROG_Z], 10, 0);
	assert_near(t->diameter, 6, 0);
	assert_string_equal(t->comment, "6 mm end mill");
	assert_int_equal(t->line, 2);
	t = sh2000_tool_table_find(&T, 2);
	assert_non_null(t);
	assert_pos4(t->offset, 0.5, 0, -1, 2);
	assert_near(t->front_angle, 10, 0);
	assert_near(t->back_angle, 20, 0);
	assert_int_equal(t->orientation, 3);
	assert_null(t->comment);
	t = sh2000_tool_table_find(&T, 3);
	assert_non_null(t);
	assert_int_equal(t->pocket, 7);
	assert_null(t->comment);	/* ';' with nothing after it */
	assert_null(sh2000_tool_table_find(&T, 4));
	assert_null(sh2000_tool_table_find(NULL, 1));
}

/* One bad table line: the error's code and column, the table empty. */
static void bad_table(const char *text, enum sh2000_prog_diag_code code,
		      unsigned int line, unsigned int col)
{
	struct sh2000_tool_table t;
	const struct sh2000_prog_diag *e;

	sh2000_tool_table_init(&t);
	sh2000_prog_diags_free(&D);
	sh2000_prog_diags_init(&D);
	assert_int_equal(sh2000_tool_table_read(&t, "bad.tbl", text,
						strlen(text), &D),
			 -SH2000_PROG_EINVALID);
	e = first_error();
	assert_non_null(e);
	if (e->code != code || e->pos.line != line || e->pos.column != col) {
		fprintf(stderr, "for: %s", text);
		dump();
	}
	assert_int_equal(e->code, code);
	assert_int_equal(e->pos.line, line);
	assert_int_equal(e->pos.column, col);
	assert_string_equal(e->pos.file, "bad.tbl");
	assert_int_equal(t.count, 0);
	assert_null(t.tools);
	sh2000_tool_table_free(&t);
}

static void test_table_bad_lines(void **state)
{
	char buf[256];

	(void)state;
	bad_table("T1 P1 K5\n", SH2000_PD_UNKNOWN, 1, 7);
	bad_table("T1 P1 Zabc\n", SH2000_PD_SYNTAX, 1, 7);
	bad_table("T1 P1 Znan\n", SH2000_PD_SYNTAX, 1, 7);
	bad_table("T1 P1 Z\n", SH2000_PD_SYNTAX, 1, 7);
	bad_table("T1 P1 Z 10\n", SH2000_PD_SYNTAX, 1, 7);
	bad_table("T1 P1 Z1 Z2\n", SH2000_PD_CONFLICT, 1, 10);
	bad_table("P1 Z1\n", SH2000_PD_MISSING, 1, 1);
	bad_table("T1 Z1\n", SH2000_PD_MISSING, 1, 1);
	bad_table("T0 P1\n", SH2000_PD_RANGE, 1, 1);
	bad_table("T1.5 P1\n", SH2000_PD_RANGE, 1, 1);
	bad_table("T1 P-1\n", SH2000_PD_RANGE, 1, 4);
	bad_table("T1 P1 Q1.5\n", SH2000_PD_RANGE, 1, 7);
	bad_table("T1 P1 Z1e300\n", SH2000_PD_RANGE, 1, 7);
	bad_table("T1 P1 B1\n", SH2000_PD_NO_AXIS, 1, 7);
	bad_table("T1 P1 W-2\n", SH2000_PD_NO_AXIS, 1, 7);
	bad_table("T1 P1\n; two of one tool\nT1 P2 Z3\n", SH2000_PD_CONFLICT, 3, 1);
	bad_table("T1 P1 Z1\n  T2 P2 Y1 #5\n", SH2000_PD_UNKNOWN, 2, 12);
	/* every bad line is reported, each at its place */
	bad_table("T1 P1 K1\nT2 P2\nT3\nT4 P4 Zx\n", SH2000_PD_UNKNOWN, 1, 7);
	assert_int_equal(D.errors, 3);
	sh2000_prog_diag_format(&D.items[2], buf, sizeof(buf));
	assert_non_null(strstr(buf, "bad.tbl:4:7: error: Z: 'x' is not a finite number"));
}

static void test_table_file(void **state)
{
	char path[] = "/tmp/sh2000-tbl-XXXXXX";
	int fd = mkstemp(path);
	const struct sh2000_prog_diag *e;

	(void)state;
	assert_true(fd >= 0);
	assert_int_equal(write(fd, table_text, strlen(table_text)),
			 (ssize_t)strlen(table_text));
	close(fd);
	assert_int_equal(sh2000_tool_table_read_file(&T, path, &D), 0);
	assert_int_equal(T.count, 3);
	assert_string_equal(T.file, path);
	unlink(path);
	assert_int_equal(sh2000_tool_table_read_file(&T, path, &D), -ENOENT);
	assert_int_equal(T.count, 0);
	e = first_error();
	assert_non_null(e);
	assert_int_equal(e->pos.line, 0);
	assert_non_null(strstr(e->message, "cannot read the tool table"));
}

/* The table's lengths are mm (the machine's units), whatever the
 * program's: T1's Z+10 is 10 mm under G20 too. */
static void test_table_units(void **state)
{
	(void)state;
	expect_tools_ok(G, "G20\nT1 M6 G43\nG0 X1 Z1\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 25.4, 0, 25.4 + 10, 0);
	/* A offsets are mm, as A words are */
	expect_tools_ok(G, "G20 G43 H2\nG0 Z0 A1\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, -1, 3);
}

static void test_g43(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	/* LinuxCNC: programmed Z is the tip; the machine goes Z + offset */
	expect_tools_ok(G, "T1 M6 G43 H1\nG0 X1 Z5\nG1 Z-1 F600\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 1, 0, 15, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 1, 0, 9, 0);
	/* G43 without H: the tool in the spindle (after M6, not after T) */
	expect_tools_ok(G, "T1\nG43\nG0 Z5\nM6\nG43\nG0 Z5\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 5, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 0, 15, 0);
	/* H0 and tool 0: no offset */
	expect_tools_ok(G, "G43 H1\nG43 H0\nG0 Z5\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 5, 0);
	/* X offsets too (tool 2); an absolute arc centre is the tip's */
	expect_tools_ok(G, "G43 H2\nG0 X10 Y0 Z0\nG90.1 G3 X0 Y10 I0 J0 F60\nM2\n",
			false);
	/* A is not named: the machine's A stays */
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 10.5, 0, -1, 0);
	b = nth(SH2000_PROG_ARC, 0);
	assert_pos4(b->end, 0.5, 10, -1, 0);
	assert_near(b->u.arc.centre[0], 0.5, 1e-12);
	assert_near(b->u.arc.centre[1], 0, 1e-12);
	/* the machine does not move at G43 or G49: a later move without Z
	 * keeps the machine's Z; G91 distances are the same for both */
	expect_tools_ok(G, "G0 Z5\nG43 H1\nG0 X1\nG91 G0 Z1\nG90 G49\nG0 X2\nG0 Z0\nM2\n",
			false);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 1, 0, 5, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 2)->end, 1, 0, 6, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 3)->end, 2, 0, 6, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 4)->end, 2, 0, 0, 0);
	/* G43.2 adds a tool's offsets */
	expect_tools_ok(G, "G43 H1\nG43.2 H2\nG0 Z0\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 9, 0);
	/* NURBS control points are the tip's too */
	expect_tools_ok(G, "G43 H2\nG0 X0 Y0 Z0\nF600\nG5.2 X1 Y1 P1\nX2 Y0 P1\nG5.3\nM2\n",
			false);
	b = nth(SH2000_PROG_NURBS, 0);
	assert_pos4(b->u.nurbs.points[1], 1.5, 1, -1, 0);
	assert_pos4(b->end, 2.5, 0, -1, 0);
}

static void test_g43_1(void **state)
{
	(void)state;
	/* in the program's units; A always mm */
	expect_tools_ok(G, "G43.1 Z2\nG0 Z0\nG20\nG43.1 Z1 A1\nG0 Z0 A0\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 2, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 0, 25.4, 1);
	/* G43.1's axis words are its offset: no move, unless the line has a
	 * motion word too (then both, as LinuxCNC) */
	expect_tools_ok(G, "G1 X1 F600\nG43.1 Z1 X3\nX2\nG43.1 Z2 G1 X1\nM2\n", false);
	assert_int_equal(count_kind(SH2000_PROG_LINE), 3);
	assert_pos4(nth(SH2000_PROG_LINE, 1)->end, 5, 0, 0, 0);
	/* rs274: USE_TOOL_LENGTH_OFFSET(1 0 2, ...), STRAIGHT_FEED(1, 0, 2) */
	assert_pos4(nth(SH2000_PROG_LINE, 2)->end, 2, 0, 4, 0);
	/* G43.1 alone: no offset; G49 the same */
	expect_tools_ok(G, "G43.1 Z5\nG43.1\nG0 Z0\nG43.1 Z5\nG49\nG0 Z1\nM2\n", false);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 0, 0);
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 0, 1, 0);
	/* without a table: G43.1 needs none */
	expect_ok(G, "G43.1 Z1\nG0 Z0\nM2\n");
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 1, 0);
}

static void test_tool_errors(void **state)
{
	(void)state;
	/* LinuxCNC: "Requested tool 9 not found in the tool table" */
	expect_tools_error("G43 H9\nM2\n", SH2000_PD_TOOL, 1, 5);
	expect_tools_error("T9\nM2\n", SH2000_PD_TOOL, 1, 1);
	expect_tools_error("G0 X1\nT1 M6\nG43 H1.5\nM2\n", SH2000_PD_RANGE, 3, 5);
	expect_tools_error("T-1\nM2\n", SH2000_PD_RANGE, 1, 1);
	expect_tools_error("G0 X1 H1\nM2\n", SH2000_PD_CONFLICT, 1, 7);
	expect_tools_error("G49 H1\nM2\n", SH2000_PD_CONFLICT, 1, 5);
	expect_tools_error("G43.1 Z1 H1\nM2\n", SH2000_PD_CONFLICT, 1, 10);
	expect_tools_error("G43.1 K1\nM2\n", SH2000_PD_CONFLICT, 1, 7);
	expect_tools_error("G43.1 X1 Z9999999999\nM2\n", SH2000_PD_RANGE, 1, 10);
	expect_tools_error("G0 X0\nG43.2 Z1\nM2\n", SH2000_PD_UNSUPPORTED, 2, 1);
	expect_tools_error("G0 X0\nG43.2 H1 Z1\nM2\n", SH2000_PD_UNSUPPORTED, 2, 1);
	expect_tools_error("G43 G49\nM2\n", SH2000_PD_CONFLICT, 1, 5);
	expect_tools_error("T1 M6 M6\nM2\n", SH2000_PD_CONFLICT, 1, 7);
	/* without a table: T and M6 are only reported, offsets of a tool
	 * are errors that say so */
	expect_ok(G, "T1 M6\nG43 H0\nG0 X1\nM2\n");
	expect_error(G, "G43 H1\nM2\n", SH2000_PD_TOOL, 1, 5);
	assert_non_null(strstr(first_error()->message, "no tool table was given"));
	expect_error(G, "T1 M6\nG43\nM2\n", SH2000_PD_TOOL, 2, 1);
}

/* A tool change is reported once, or (when asked) is a pause before the
 * line's motion, naming the tool. */
static void test_tool_change(void **state)
{
	const struct sh2000_prog_block *b;

	(void)state;
	expect_tools_ok(G, "T1 M6 G43 H1\nG0 X1\nT2 M6\nT0 M6\nM2\n", false);
	assert_int_equal(count_kind(SH2000_PROG_PAUSE), 0);
	assert_int_equal(count_warnings(SH2000_PD_NOT_ACTED), 2);
	assert_true(has_message("M6 (tool change) not paused at"));
	assert_true(has_message("T1 (tool select) not acted on"));
	expect_tools_ok(G, "T1 M6 G43 H1\nG0 X1\nT2 M6 G0 X2\nM6\nT0 M6\nM2\n", true);
	assert_int_equal(count_warnings(SH2000_PD_NOT_ACTED), 1);	/* T */
	assert_false(has_message("not paused at"));
	assert_int_equal(count_kind(SH2000_PROG_PAUSE), 4);
	b = nth(SH2000_PROG_PAUSE, 0);
	assert_true(b->tool_change);
	assert_false(b->u.optional);
	assert_int_equal(b->tool, 1);
	assert_int_equal(b->pos.line, 1);
	assert_int_equal(b->pos.column, 4);
	/* the pause comes before the motion of its line (LinuxCNC's order) */
	b = nth(SH2000_PROG_PAUSE, 1);
	assert_int_equal(b->tool, 2);
	assert_true(b + 1 == nth(SH2000_PROG_RAPID, 1));
	assert_int_equal(nth(SH2000_PROG_PAUSE, 2)->tool, 2);	/* M6 again */
	assert_int_equal(nth(SH2000_PROG_PAUSE, 3)->tool, 0);
	/* M0 is no tool change */
	expect_tools_ok(G, "M0\nM2\n", true);
	assert_false(nth(SH2000_PROG_PAUSE, 0)->tool_change);
}

/* A program that starts as CAM output does, read end to end. */
static void test_cam_start(void **state)
{
	(void)state;
	expect_tools_ok(G, "%\n(T1  D=6 CR=0 - ZMIN=-1 - flat end mill)\nG90 G94 G17\nG21\n"
			   "T1 M6\nS10000 M3\nG54\nG0 X0 Y0\nG43 Z15 H1\nG1 Z-1 F300\n"
			   "G1 X20\nM5\nG49\nM30\n%\n", false);
	/* "G43 Z15 H1" applies the offset, then moves there (modal G0) */
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 0, 25, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 1)->end, 20, 0, 9, 0);
	assert_int_equal(nth(SH2000_PROG_END, 0)->u.end_code, 30);
}

/* rs274's USE_TOOL_LENGTH_OFFSET in its units, and its tool changes. */
static void test_canon_offsets(void **state)
{
	(void)state;
	expect_tools_ok(CANON,
		"    1 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
		"    2 N..... SELECT_TOOL(1)\n"
		"    3 N..... START_CHANGE()\n"
		"    4 N..... CHANGE_TOOL(1)\n"
		"    5 N..... USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 1.0000, 2.0000 0.0000 0.0000, 0.0000 0.0000 0.0000)\n"
		"    6 N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)\n"
		"    7 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
		"    8 N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)\n"
		"    9 N..... USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000)\n"
		"   10 N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)\n"
		"   11 N..... PROGRAM_END()\n", true);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 0, 0, 2 * 25.4, 2);
	/* the offset keeps its length when the units change */
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 0, 0, 1 + 25.4, 2);
	assert_pos4(nth(SH2000_PROG_RAPID, 2)->end, 1, 0, 1, 0);
	assert_int_equal(nth(SH2000_PROG_PAUSE, 0)->tool, 1);
	assert_true(nth(SH2000_PROG_PAUSE, 0)->tool_change);
	/* SELECT_TOOL is checked against the table when there is one */
	assert_int_equal(rd_tools(CANON, "    1 N..... SELECT_TOOL(9)\n"
				  "    2 N..... PROGRAM_END()\n", false),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(first_error()->code, SH2000_PD_TOOL);
	assert_int_equal(rd_tools(CANON, "    1 N..... CHANGE_TOOL(1.5)\n"
				  "    2 N..... PROGRAM_END()\n", false),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(first_error()->code, SH2000_PD_RANGE);
	assert_int_equal(rd_tools(CANON, "    1 N..... USE_TOOL_LENGTH_OFFSET(0 0 1e300, 0 0 0, 0 0 0)\n"
				  "    2 N..... PROGRAM_END()\n", false),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(first_error()->code, SH2000_PD_RANGE);
}

/* LinuxCNC 2.9's interpreter keeps a tool offset's number across a units
 * change (G21 G43 H2 with 25.4 mm, G20, G49: its next move without Z goes
 * to Z 25.4 in); this reader keeps it in mm and says where they differ. */
static void test_offset_units_warning(void **state)
{
	(void)state;
	expect_tools_ok(G, "G21 G43 H3\nG0 Z0\nG20\nG49\nG0 X1\nG43 H3\nG49\nM2\n", false);
	assert_int_equal(count_warnings(SH2000_PD_ORDER), 1);
	assert_true(has_message("set under G21 is changed under G20"));
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->end, 25.4, 0, 25.4, 0);
	expect_tools_ok(G, "G20\nG43 H3\nG0 Z0\nG49\nG21 G43 H3\nG49\nM2\n", false);
	assert_int_equal(count_warnings(SH2000_PD_ORDER), 0);
}

int main(void)
{
#define T_(f) cmocka_unit_test_setup_teardown(f, tab_setup, tab_teardown)
	const struct CMUnitTest tests[] = {
		T_(test_table_good),
		T_(test_table_bad_lines),
		T_(test_table_file),
		T_(test_table_units),
		T_(test_g43),
		T_(test_g43_1),
		T_(test_tool_errors),
		T_(test_tool_change),
		T_(test_cam_start),
		T_(test_canon_offsets),
		T_(test_offset_units_warning),
	};
#undef T_

	return cmocka_run_group_tests(tests, NULL, NULL);
}
