// SPDX-License-Identifier: MIT
/*
 * The planner through the card model (libsh2000's `sim` card: protocol,
 * firmware fine interpolation, PID, plant): the card's own fine set-points
 * stay within every axis limit, follow the exact circle within a fraction
 * of a micrometre when compensated, the card accepts every record (no
 * velocity rejection, no underrun) and ends exactly on the end point.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "plcard.h"

struct fine_acc {
	const struct sh2000_path_config *c;
	double h, prev[2][4];
	uint64_t n;
	double v_ratio, a_ratio;
	double cx, cy, R, circ_max;	/* R > 0: measure the circle */
};

static void fine_fn(void *ctx, const double x[4], const double act[4])
{
	struct fine_acc *f = ctx;
	unsigned int a;

	(void)act;
	if (f->n >= 1)
		for (a = 0; a < 4; a++)
			f->v_ratio = fmax(f->v_ratio, fabs(x[a] - f->prev[1][a]) /
					  f->h / f->c->vmax[a]);
	if (f->n >= 2)
		for (a = 0; a < 4; a++)
			f->a_ratio = fmax(f->a_ratio,
					  fabs(x[a] - 2 * f->prev[1][a] +
					       f->prev[0][a]) /
					  (f->h * f->h) / f->c->amax[a]);
	if (f->R > 0)
		f->circ_max = fmax(f->circ_max, fabs(hypot(x[0] - f->cx,
							   x[1] - f->cy) - f->R));
	memcpy(f->prev[0], f->prev[1], sizeof(f->prev[0]));
	memcpy(f->prev[1], x, sizeof(f->prev[1]));
	f->n++;
}

static void run(int raw, int circle)
{
	static struct plcard pc;
	struct sh2000_path_config c;
	struct sh2000_path *p;
	struct fine_acc acc;
	struct sh2000_status st;
	double o[4], end[4];
	unsigned int a;
	int r;

	sh2000_path_config_default(&c);
	r = plcard_open(&pc, c.vmax, c.amax, 1, o);
	if (r)
		print_error("card: %s\n", pc.msg);
	assert_int_equal(r, 0);
	if (raw)
		c.output = SH2000_OUTPUT_RAW;
	memcpy(c.start, o, sizeof(c.start));
	memset(&acc, 0, sizeof(acc));
	acc.c = &c;
	acc.h = c.period_s / c.fine_steps;
	pc.fn = fine_fn;
	pc.ctx = &acc;
	assert_int_equal(sh2000_path_create(&p, &c, plcard_sink, &pc, NULL, 0), 0);
	pc.record = 1;
	memcpy(end, o, sizeof(end));
	if (circle) {
		struct sh2000_path_arc arc;

		memset(&arc, 0, sizeof(arc));
		arc.plane = SH2000_PLANE_XY;
		memcpy(arc.end, o, sizeof(arc.end));
		arc.centre[0] = o[0] - 5;
		arc.centre[1] = o[1];
		arc.ccw = 1;
		acc.cx = o[0] - 5;
		acc.cy = o[1];
		acc.R = 5;
		assert_int_equal(sh2000_path_arc(p, &arc, 300), 0);
	} else {
		static const double d[][4] = {
			{ 10, 0, 0, 0 }, { 10, 10, 0, 0 }, { 12, 11, 1, 0.5 },
			{ -20, 11, -3, 0.5 }, { 0, 0, 0, 0 },
		};
		unsigned int i;

		for (i = 0; i < 5; i++) {
			for (a = 0; a < 4; a++)
				end[a] = o[a] + d[i][a];
			assert_int_equal(sh2000_path_line(p, end, 400), 0);
		}
	}
	r = sh2000_path_finish(p);
	if (!r)
		r = plcard_idle(&pc);
	if (r)
		print_error("run: %s / %s\n", sh2000_path_error(p), pc.msg);
	assert_int_equal(r, 0);
	pc.record = 0;
	print_message("%s %s: %llu fine points, v %.4f a %.4f of the limits, circle %.5f mm\n",
		      circle ? "circle" : "lines", raw ? "raw" : "compensated",
		      (unsigned long long)acc.n, acc.v_ratio, acc.a_ratio,
		      acc.circ_max);
	assert_true(acc.n > 1000);
	assert_true(acc.v_ratio <= 1.0);
	assert_true(acc.a_ratio <= 1.0);
	if (circle)
		assert_true(acc.circ_max <= (raw ? 0.02 : 0.001));
	/* the card ends exactly on the end point, nothing rejected */
	assert_int_equal(sh2000_poll(pc.h, &st), 0);
	assert_int_equal(st.card_faults, 0);
	assert_int_equal(st.reject_count, 0);
	for (a = 0; a < 4; a++)
		assert_int_equal(st.axis[a].cmd_counts,
				 (int32_t)llround(end[a] * pc.scale));
	sh2000_path_destroy(p);
	plcard_close(&pc);
}

static void test_card_circle_compensated(void **s) { (void)s; run(0, 1); }
static void test_card_circle_raw(void **s) { (void)s; run(1, 1); }
static void test_card_lines_compensated(void **s) { (void)s; run(0, 0); }
static void test_card_lines_raw(void **s) { (void)s; run(1, 0); }

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_card_circle_compensated),
		cmocka_unit_test(test_card_circle_raw),
		cmocka_unit_test(test_card_lines_compensated),
		cmocka_unit_test(test_card_lines_raw),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
