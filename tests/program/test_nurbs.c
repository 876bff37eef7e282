/* SPDX-License-Identifier: MIT */
/* G5.2/G5.3 NURBS blocks as LinuxCNC reads them, and NURBS evaluation. */
#include "progtest.h"

/* LinuxCNC's documentation example (g-code.adoc, G5.2 G5.3) */
static const char doc_example[] =
	"G0 X0 Y0 (rapid move)\n"
	"F10 (set feed rate)\n"
	"G5.2 P1 L3\n"
	"     X0 Y1 P1\n"
	"     X2 Y2 P1\n"
	"     X2 Y0 P1\n"
	"     X0 Y0 P2\n"
	"G5.3\n"
	"; The rapid moves show the same path without the NURBS Block\n"
	"G0 X0 Y1\n"
	"   X2 Y2\n"
	"   X2 Y0\n"
	"   X0 Y0\n"
	"M2\n";

static void test_doc_example(void **state)
{
	const struct sh2000_prog_block *b;
	const struct sh2000_nurbs *n;
	static const double pts[5][2] = { {0, 0}, {0, 1}, {2, 2}, {2, 0}, {0, 0} };
	static const double w[5] = { 1, 1, 1, 1, 2 };
	static const double knots[8] = { 0, 0, 0, 1, 2, 3, 3, 3 };
	double p[4];

	(void)state;
	expect_ok(G, doc_example);
	assert_int_equal(count_kind(SH2000_PROG_NURBS), 1);
	b = nth(SH2000_PROG_NURBS, 0);
	n = &b->u.nurbs;
	assert_int_equal(b->pos.line, 3);
	assert_int_equal(b->pos.column, 1);
	assert_near(b->feed, 10.0 / 60, 1e-12);
	assert_int_equal(n->degree, 2);
	assert_int_equal(n->npoints, 5);
	for (int i = 0; i < 5; i++) {
		assert_near(n->points[i][0], pts[i][0], 0);
		assert_near(n->points[i][1], pts[i][1], 0);
		assert_near(n->weights[i], w[i], 0);
	}
	for (int i = 0; i < 8; i++)
		assert_near(n->knots[i], knots[i], 0);
	assert_pos4(b->start, 0, 0, 0, 0);
	assert_pos4(b->end, 0, 0, 0, 0);
	/* clamped: the curve starts and ends on the end control points */
	sh2000_prog_block_point(b, 0, p);
	assert_pos4(p, 0, 0, 0, 0);
	sh2000_prog_block_point(b, 1, p);
	assert_pos4(p, 0, 0, 0, 0);
	/* at u = 1 only control points 1 and 2 count, half each */
	sh2000_nurbs_eval(n, 1, p, NULL, NULL);
	assert_near(p[0], 1, 1e-12);
	assert_near(p[1], 1.5, 1e-12);
	/* the rapids after the block start at its end */
	assert_pos4(nth(SH2000_PROG_RAPID, 1)->start, 0, 0, 0, 0);
	assert_int_equal(count_kind(SH2000_PROG_END), 1);
}

static void test_weights_order_units(void **state)
{
	const struct sh2000_nurbs *n;

	(void)state;
	/* P without X Y on the opening line weighs the start point; L4 is a
	 * cubic; Z and A stay */
	expect_ok(G, "G0 X1 Y1 Z3 A4\nG1 F60\nG5.2 P3 L4\nX2 Y1 P1\nX3 Y2 P0.5\nG5.2 X4 Y1 P1\nG5.3\n" "M2\n");
	n = &nth(SH2000_PROG_NURBS, 0)->u.nurbs;
	assert_int_equal(n->degree, 3);
	assert_int_equal(n->npoints, 4);
	assert_near(n->weights[0], 3, 0);
	assert_near(n->weights[1], 1, 0);
	assert_near(n->weights[2], 0.5, 0);
	assert_near(n->weights[3], 1, 0);
	assert_pos4(n->points[0], 1, 1, 3, 4);
	assert_pos4(n->points[3], 4, 1, 3, 4);
	/* 4 points of order 4: one Bezier segment, knots 0000 1111 */
	for (int i = 0; i < 8; i++)
		assert_near(n->knots[i], i < 4 ? 0 : 1, 0);
	assert_pos4(nth(SH2000_PROG_NURBS, 0)->end, 4, 1, 3, 4);
	/* inches */
	expect_ok(G, "G20 F1\nG5.2 X1 Y0 P1\nX1 Y1 P1\nG5.3\n" "M2\n");
	/* without P on the opening line the start point weighs 1 */
	assert_near(nth(SH2000_PROG_NURBS, 0)->u.nurbs.weights[0], 1, 0);
	n = &nth(SH2000_PROG_NURBS, 0)->u.nurbs;
	assert_near(n->points[2][1], 25.4, 1e-12);
	assert_int_equal(n->degree, 2);
}

static void test_nurbs_errors(void **state)
{
	(void)state;
	/* not closed; closed without opening; too few points */
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nX2 Y2 P1\n", SH2000_PD_NURBS, 2, 1);
	expect_error(G, "G5.3\n", SH2000_PD_NURBS, 1, 1);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nG5.3\n", SH2000_PD_NURBS, 3, 1);
	expect_error(G, "F1\nG5.2 X1 Y1 L4 P1\nX2 Y2 P1\nG5.3\n", SH2000_PD_NURBS, 4, 1);
	/* other words inside the block */
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nG1 X2\nG5.3\n", SH2000_PD_NURBS, 3, 1);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nX2 Y2 F5\nG5.3\n", SH2000_PD_NURBS, 3, 7);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nM0\nG5.3\n", SH2000_PD_NURBS, 3, 1);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nX2 Y2 Z1\nG5.3\n", SH2000_PD_NURBS, 3, 7);
	/* words */
	expect_error(G, "F1\nG5.2 X1\n", SH2000_PD_MISSING, 2, 6);
	expect_error(G, "F1\nG5.2 X1 Y1 P0\n", SH2000_PD_RANGE, 2, 12);
	expect_error(G, "F1\nG5.2 X1 Y1 P-1\n", SH2000_PD_RANGE, 2, 12);
	expect_error(G, "F1\nG5.2 X1 Y1 P1 L2\n", SH2000_PD_RANGE, 2, 15);
	expect_error(G, "F1\nG5.2 X1 Y1 P1 L3.5\n", SH2000_PD_RANGE, 2, 15);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nP2\nX2 Y2 P1\nG5.3\n", SH2000_PD_CONFLICT, 3, 1);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nG5.2 P2\nX2 Y2 P1\nG5.3\n", SH2000_PD_NURBS, 3, 6);
	expect_error(G, "F1\nG5.3 X1 Y1\n", SH2000_PD_CONFLICT, 2, 1);
	/* every control point needs its weight, as LinuxCNC's interpreter
	 * demands (its manual says 1 by default) */
	expect_error(G, "F1\nG5.2 X1 Y1\n", SH2000_PD_MISSING, 2, 6);
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nX2 Y2\nG5.3\n", SH2000_PD_MISSING, 3, 1);
	/* modes */
	expect_error(G, "G5.2 X1 Y1 P1\n", SH2000_PD_FEED, 1, 1);
	expect_error(G, "F1 G18\nG5.2 X1 Y1 P1\n", SH2000_PD_UNSUPPORTED, 2, 1);
	expect_error(G, "F1 G91\nG5.2 X1 Y1 P1\n", SH2000_PD_UNSUPPORTED, 2, 1);
	/* a failed G5.2 line is reported once, not again at each point */
	assert_int_equal(rd(G, "F1 G18\nG5.2 X1 Y1 P1\nX2 Y2 P1\nX3 Y3 P1\nG5.3\nG17 G0 X0\nM2\n"),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 1);
	/* ... but a G5.3 after other motion is an error again */
	assert_int_equal(rd(G, "F1 G18\nG5.2 X1 Y1 P1\nG1 X2\nG5.3\nM2\n"),
			 -SH2000_PROG_EINVALID);
	assert_int_equal(D.errors, 2);
	assert_int_equal(D.items[1].pos.line, 4);
	/* after G5.3 there is no motion mode */
	expect_error(G, "F1\nG5.2 X1 Y1 P1\nX2 Y2 P1\nG5.3\nX3 Y3\n", SH2000_PD_MISSING, 5, 1);
}

static void test_eval_rational_circle(void **state)
{
	/* a quarter of the unit circle as a rational quadratic Bezier */
	double pts[3][4] = { {1, 0, 0, 0}, {1, 1, 0, 0}, {0, 1, 0, 0} };
	double w[3] = { 1, M_SQRT1_2, 1 };
	double k[6] = { 0, 0, 0, 1, 1, 1 };
	struct sh2000_nurbs n = { 2, 3, pts, w, k };
	double p[4];

	(void)state;
	for (int i = 0; i <= 10; i++) {
		sh2000_nurbs_eval(&n, i / 10.0, p, NULL, NULL);
		assert_near(hypot(p[0], p[1]), 1, 1e-12);
	}
	sh2000_nurbs_eval(&n, 0.5, p, NULL, NULL);
	assert_near(p[0], M_SQRT1_2, 1e-12);
	/* outside the domain it clamps */
	sh2000_nurbs_eval(&n, 7, p, NULL, NULL);
	assert_near(p[0], 0, 1e-12);
	assert_near(p[1], 1, 1e-12);
}

static void test_eval_non_uniform(void **state)
{
	/* degree 1 with non-uniform knots is the polyline, parameterised by
	 * the knots: u = 0.25 lies on the second leg's start */
	double pts[3][4] = { {0, 0, 0, 0}, {10, 0, 0, 0}, {10, 10, 0, 0} };
	double w[3] = { 1, 1, 1 };
	double k[5] = { 0, 0, 0.25, 1, 1 };
	struct sh2000_nurbs n = { 1, 3, pts, w, k };
	double p[4];

	(void)state;
	sh2000_nurbs_eval(&n, 0.125, p, NULL, NULL);
	assert_near(p[0], 5, 1e-12);
	sh2000_nurbs_eval(&n, 0.25, p, NULL, NULL);
	assert_near(p[0], 10, 1e-12);
	assert_near(p[1], 0, 1e-12);
	sh2000_nurbs_eval(&n, 0.625, p, NULL, NULL);
	assert_near(p[1], 5, 1e-12);
	sh2000_nurbs_eval(&n, 1, p, NULL, NULL);
	assert_near(p[1], 10, 1e-12);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_doc_example, setup, teardown),
		cmocka_unit_test_setup_teardown(test_weights_order_units, setup, teardown),
		cmocka_unit_test_setup_teardown(test_nurbs_errors, setup, teardown),
		cmocka_unit_test(test_eval_rational_circle),
		cmocka_unit_test(test_eval_non_uniform),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
