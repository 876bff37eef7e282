/* SPDX-License-Identifier: MIT */
/* CSV point lists and JSON NURBS files: good files and every error. */
#include "progtest.h"

/* ---- CSV ------------------------------------------------------------------ */

static void test_csv_plain(void **state)
{
	struct sh2000_prog_options o;

	(void)state;
	sh2000_prog_options_default(&o);
	o.feed_mm_s = 5;
	/* no header: x,y,z; the machine is already at the first point */
	expect_ok_opt(CSV, "# a square\n0,0,0\n10, 0, 0\n\n10,10,0   # corner\n", &o);
	assert_int_equal(P.count, 3);
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_FEED);
	assert_near(P.blocks[0].feed, 5, 0);
	assert_int_equal(P.blocks[0].pos.line, 3);
	assert_int_equal(P.blocks[1].kind, SH2000_PROG_LINE);
	assert_pos4(P.blocks[1].end, 10, 0, 0, 0);
	assert_near(P.blocks[1].feed, 5, 0);
	assert_int_equal(P.blocks[1].pos.line, 3);
	assert_pos4(P.blocks[2].end, 10, 10, 0, 0);
	assert_int_equal(P.blocks[2].pos.line, 5);
	/* x,y,z,a,f: f in mm/min, the first point is reached at rapid */
	expect_ok(CSV, "1,2,3,4,600\r\n5,6,7,8,\r\n9,10,11,12,1200\r\n");
	assert_int_equal(P.count, 5);
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_FEED);
	assert_near(P.blocks[0].feed, 10, 1e-12);
	assert_int_equal(P.blocks[1].kind, SH2000_PROG_RAPID);
	assert_pos4(P.blocks[1].end, 1, 2, 3, 4);
	assert_int_equal(P.blocks[2].kind, SH2000_PROG_LINE);
	assert_near(P.blocks[2].feed, 10, 1e-12);
	assert_int_equal(P.blocks[3].kind, SH2000_PROG_FEED);
	assert_near(P.blocks[4].feed, 20, 1e-12);
	assert_pos4(P.blocks[4].end, 9, 10, 11, 12);
}

static void test_csv_header(void **state)
{
	struct sh2000_prog_options o;

	(void)state;
	sh2000_prog_options_default(&o);
	o.start[2] = 7;
	/* named columns in any order; missing axes keep the position; an
	 * empty field keeps its value */
	expect_ok_opt(CSV, "Y, X, feed_mm_s\n1,2,3\n, 4,\n5,,2.5\n", &o);
	assert_pos4(nth(SH2000_PROG_RAPID, 0)->end, 2, 1, 7, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 4, 1, 7, 0);
	assert_near(nth(SH2000_PROG_LINE, 0)->feed, 3, 0);
	assert_pos4(nth(SH2000_PROG_LINE, 1)->end, 4, 5, 7, 0);
	assert_near(nth(SH2000_PROG_LINE, 1)->feed, 2.5, 0);
	expect_ok(CSV, "a,f\n1,60\n2,60\n");
	assert_pos4(nth(SH2000_PROG_LINE, 0)->end, 0, 0, 0, 2);
	assert_near(nth(SH2000_PROG_LINE, 0)->feed, 1, 1e-12);
}

static void test_csv_errors(void **state)
{
	struct sh2000_prog_options o;

	(void)state;
	expect_error(CSV, "x,y\n1,abc\n", SH2000_PD_SYNTAX, 2, 3);
	expect_error(CSV, "1,2,3\n1,2\n", SH2000_PD_SYNTAX, 2, 4);
	expect_error(CSV, "1,2,3\n1,2,3,4\n", SH2000_PD_SYNTAX, 2, 7);
	expect_error(CSV, "x,y,q\n", SH2000_PD_UNKNOWN, 1, 5);
	expect_error(CSV, "x,y,x\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(CSV, "x,f,feed_mm_s\n", SH2000_PD_CONFLICT, 1, 5);
	expect_error(CSV, "f\n1\n", SH2000_PD_MISSING, 1, 1);
	expect_error(CSV, "1,nan\n", SH2000_PD_SYNTAX, 1, 3);
	expect_error(CSV, "1, 1e999\n", SH2000_PD_RANGE, 1, 4);
	expect_error(CSV, "1,2\n3,4\n", SH2000_PD_FEED, 2, 1);
	expect_error(CSV, "1,2,0,0,0\n", SH2000_PD_RANGE, 1, 9);
	expect_error(CSV, "1,2,0,0,-5\n", SH2000_PD_RANGE, 1, 9);
	expect_error(CSV, "1\n", SH2000_PD_SYNTAX, 1, 1);
	expect_error(CSV, "1,2,3,4,5,6\n", SH2000_PD_SYNTAX, 1, 1);
	expect_error(CSV, "# nothing\n\n", SH2000_PD_MISSING, 2, 1);
	expect_error(CSV, "x,y\n", SH2000_PD_MISSING, 1, 1);
	/* every bad line is reported */
	sh2000_prog_options_default(&o);
	o.feed_mm_s = 1;
	assert_int_equal(rd_opt(CSV, "1,2\n3,x\n4,5\n6,7,8\n", &o), -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 2);
	assert_int_equal(D.items[0].pos.line, 2);
	assert_int_equal(D.items[1].pos.line, 4);
}

/* ---- JSON NURBS ------------------------------------------------------------- */

static const char curve[] =
	"{\n"
	"  \"format\": \"sh2000-nurbs-1\",\n"
	"  \"degree\": 2,\n"
	"  \"knots\": [0, 0, 0, 0.3, 1, 1, 1],\n"
	"  \"weights\": [1, 2, 1, 1],\n"
	"  \"points\": [[0, 0], [10, 0, 1], [10, 10, 2, 3], [0, 10]],\n"
	"  \"feed\": 5\n"
	"}\n";

static void test_json_curve(void **state)
{
	const struct sh2000_prog_block *b;
	const struct sh2000_nurbs *n;
	struct sh2000_prog_options o;
	double p[4];

	(void)state;
	sh2000_prog_options_default(&o);
	o.start[2] = 5;
	o.start[3] = 6;
	expect_ok_opt(JSON, curve, &o);
	/* no rapid: the curve starts at its first control point, which
	 * takes z and a from the start position */
	assert_int_equal(P.count, 2);
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_FEED);
	assert_near(P.blocks[0].feed, 5, 0);
	b = &P.blocks[1];
	assert_int_equal(b->kind, SH2000_PROG_NURBS);
	n = &b->u.nurbs;
	assert_int_equal(n->degree, 2);
	assert_int_equal(n->npoints, 4);
	assert_near(n->knots[3], 0.3, 0);
	assert_near(n->weights[1], 2, 0);
	assert_pos4(n->points[0], 0, 0, 5, 6);
	assert_pos4(n->points[1], 10, 0, 1, 6);
	assert_pos4(n->points[2], 10, 10, 2, 3);
	assert_pos4(n->points[3], 0, 10, 5, 6);
	assert_pos4(b->start, 0, 0, 5, 6);
	assert_pos4(b->end, 0, 10, 5, 6);
	assert_near(b->feed, 5, 0);
	/* the knot at 0.3 is where only control points 1 and 2 count */
	sh2000_nurbs_eval(n, 0.3, p, NULL, NULL);
	{
		/* N1 = 0.7, N2 = 0.3 at u = 0.3 for these knots */
		double w1 = 0.7 * 2, w2 = 0.3 * 1;

		assert_near(p[0], (w1 * 10 + w2 * 10) / (w1 + w2), 1e-12);
		assert_near(p[1], (w2 * 10) / (w1 + w2), 1e-12);
	}
	/* away from the first point: a rapid there first */
	o.start[0] = -1;
	expect_ok_opt(JSON, curve, &o);
	assert_int_equal(P.blocks[0].kind, SH2000_PROG_RAPID);
	assert_pos4(P.blocks[0].end, 0, 0, 5, 6);
}

static void test_json_curves(void **state)
{
	(void)state;
	expect_ok(JSON,
		  "{\"feed\": 2, \"curves\": [\n"
		  " {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[5,0]]},\n"
		  " {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[5,0],[5,5]], \"feed\": 4,\n"
		  "  \"comment\": \"up\"}\n"
		  "]}\n");
	assert_int_equal(count_kind(SH2000_PROG_NURBS), 2);
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 0);
	assert_int_equal(count_kind(SH2000_PROG_FEED), 2);
	assert_near(nth(SH2000_PROG_NURBS, 0)->feed, 2, 0);
	assert_near(nth(SH2000_PROG_NURBS, 1)->feed, 4, 0);
	assert_int_equal(nth(SH2000_PROG_NURBS, 1)->pos.line, 3);
	assert_int_equal(nth(SH2000_PROG_NURBS, 1)->pos.column, 2);
	assert_pos4(nth(SH2000_PROG_NURBS, 1)->end, 5, 5, 0, 0);
	/* a gap between curves is a rapid */
	expect_ok(JSON,
		  "{\"feed\": 2, \"curves\": [\n"
		  " {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[5,0]]},\n"
		  " {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[6,0],[6,5]]}]}\n");
	assert_int_equal(count_kind(SH2000_PROG_RAPID), 1);
	assert_int_equal(count_kind(SH2000_PROG_FEED), 1);
}

static const char bad_weight[] =
	"{\n"
	"  \"degree\": 2,\n"
	"  \"knots\": [0, 0, 0, 1, 1, 1],\n"
	"  \"weights\": [1, 0, 1],\n"
	"  \"points\": [[0, 0], [1, 0], [1, 1]],\n"
	"  \"feed\": 5\n"
	"}\n";

static void test_json_errors(void **state)
{
	(void)state;
	/* the field and index in the message, its place in the position */
	expect_error(JSON, bad_weight, SH2000_PD_NURBS, 4, 18);
	assert_true(has_message("weights[1]: must be a number > 0"));
	expect_error(JSON, "{\"degree\": 2, \"knots\": [0,0,0,1,1],\n"
			   " \"points\": [[0,0],[1,0],[1,1]], \"feed\": 1}",
		     SH2000_PD_NURBS, 1, 24);
	assert_true(has_message("knots: 5 knots, expected points + degree + 1 = 3 + 2 + 1 = 6"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,2,1,1,1],\n"
			   " \"points\": [[0,0],[1,0],[1,1],[2,2]], \"feed\": 1}",
		     SH2000_PD_NURBS, 1, 31);
	assert_true(has_message("knots[3]: 1 is less than knots[2] = 2"));
	expect_error(JSON, "{\"degree\": 0, \"knots\": [0,1], \"points\": [[0,0]], \"feed\": 1}",
		     SH2000_PD_RANGE, 1, 12);
	assert_true(has_message("degree: must be an integer"));
	expect_error(JSON, "{\"degree\": 1.5, \"knots\": [0,1], \"points\": [[0,0]], \"feed\": 1}",
		     SH2000_PD_RANGE, 1, 12);
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"feed\": 1}",
		     SH2000_PD_MISSING, 1, 1);
	assert_true(has_message("\"points\" missing"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,2,3,4,5]], \"feed\": 1}",
		     SH2000_PD_SYNTAX, 1, 52);
	assert_true(has_message("points[1]: a point is"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,\"a\"]], \"feed\": 1}",
		     SH2000_PD_SYNTAX, 1, 55);
	assert_true(has_message("points[1][1]: must be a finite number"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,1]], \"feed\": 1,\n \"wieghts\": [1,1]}",
		     SH2000_PD_UNKNOWN, 2, 13);
	assert_true(has_message("wieghts: unknown field"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,1]]}",
		     SH2000_PD_FEED, 1, 1);
	{
		/* the caller's feed stands in */
		struct sh2000_prog_options o;

		sh2000_prog_options_default(&o);
		o.feed_mm_s = 3;
		expect_ok_opt(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,1]]}", &o);
		assert_near(nth(SH2000_PROG_NURBS, 0)->feed, 3, 0);
	}
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,1]], \"feed\": -1}",
		     SH2000_PD_RANGE, 1, 68);
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"weights\": [1], \"points\": [[0,0],[1,1]], \"feed\": 1}",
		     SH2000_PD_NURBS, 1, 46);
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,1e999]], \"feed\": 1}",
		     SH2000_PD_SYNTAX, 1, 55);
	assert_true(has_message("points[1][1]: must be a finite number"));
	/* the curve would break, or has no domain */
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,0,1,1,2,2], \"points\": [[0,0],[1,0],[1,1],[2,2]], \"feed\": 1}",
		     SH2000_PD_NURBS, 1, 24);
	assert_true(has_message("knots[3]: value 1 repeated 2 times"));
	expect_error(JSON, "{\"degree\": 1, \"knots\": [0,1,1,1], \"points\": [[0,0],[1,0]], \"feed\": 1}",
		     SH2000_PD_NURBS, 1, 24);
	/* JSON itself */
	expect_error(JSON, "{\n  \"degree\": 1,\n  \"knots\": [0, 0, 1 1]\n}\n", SH2000_PD_SYNTAX, 3, 21);
	expect_error(JSON, "{\"degree\": 1", SH2000_PD_SYNTAX, 1, 13);
	expect_error(JSON, "{} x", SH2000_PD_SYNTAX, 1, 4);
	expect_error(JSON, "[1, 2]", SH2000_PD_SYNTAX, 1, 1);
	expect_error(JSON, "{\"format\": \"other\"}", SH2000_PD_UNSUPPORTED, 1, 12);
	/* in a list of curves the message names the curve */
	expect_error(JSON, "{\"feed\": 1, \"curves\": [\n"
			   " {\"degree\": 1, \"knots\": [0,0,1,1], \"points\": [[0,0],[1,0]]},\n"
			   " {\"degree\": 1, \"knots\": [0,0,1,1], \"weights\": [1, -1], \"points\": [[1,0],[1,1]]}]}\n",
		     SH2000_PD_NURBS, 3, 51);
	assert_true(has_message("curves[1].weights[1]: must be a number > 0"));
	expect_error(JSON, "{\"feed\": 1, \"curves\": []}", SH2000_PD_SYNTAX, 1, 23);
	expect_error(JSON, "{\"feed\": 1, \"curves\": [1]}", SH2000_PD_SYNTAX, 1, 24);
	assert_true(has_message("curves[1]: a curve is an object") ||
		    has_message("curves[0]: a curve is an object"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_csv_plain, setup, teardown),
		cmocka_unit_test_setup_teardown(test_csv_header, setup, teardown),
		cmocka_unit_test_setup_teardown(test_csv_errors, setup, teardown),
		cmocka_unit_test_setup_teardown(test_json_curve, setup, teardown),
		cmocka_unit_test_setup_teardown(test_json_curves, setup, teardown),
		cmocka_unit_test_setup_teardown(test_json_errors, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
