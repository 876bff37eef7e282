// SPDX-License-Identifier: MIT
/*
 * Compensation tables (docs/compensation.md) on the in-process `sim`:
 * the interpolation's continuity (value and slope across every point, at
 * the ends and through the run-outs); loading and the status; every kind
 * of bad table refused with FILE:LINE and nothing changed on the card, by
 * the host and by the card itself (a page's check word, the image's sum,
 * a table the host did not check, a switch while moving); no step in the
 * set-point when a switch blends or a point is crossed; a table on one
 * side of a gantry pair. The corrected path after a calibration:
 * test_comp_path.c.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "calib.h"
#include "sh2000/sh2000_protocol.h"

static const double unit_scale[SH2000_AXES] = { 1e5, 1e5, 1e5, 1e5 };
static char path[64];

static void write_file(const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

static struct sh2000_comp_file *read_file(const char *text)
{
	struct sh2000_comp_file *f = NULL;
	char msg[256];

	write_file(text);
	if (sh2000_comp_file_read(&f, path, unit_scale, msg, sizeof(msg)))
		fail_msg("%s", msg);
	return f;
}

/* ---- continuity ---- */

static void eval_at(const uint16_t *w, const struct sh2000_comp_desc *t,
		    double u, double v, double out[3])
{
	double pos[SH2000_AXES] = { 0 }, d[2], dd[3];

	pos[t->src1] = u;
	if (t->kind == SH2000_COMP_GRID)
		pos[t->src2] = v;
	out[0] = sh2000_comp_eval_table(w, t, pos, d, dd);
	out[1] = d[0];
	out[2] = d[1];
}

/* Value and both slopes the same on either side of p (in counts). */
static void continuous(const uint16_t *w, const struct sh2000_comp_desc *t,
		       double u, double v, int along_v)
{
	const double eps = 1e-3;
	double lo[3], hi[3];

	eval_at(w, t, u - (along_v ? 0 : eps), v - (along_v ? eps : 0), lo);
	eval_at(w, t, u + (along_v ? 0 : eps), v + (along_v ? eps : 0), hi);
	/* over 2 eps the value moves by its slope times 2 eps, no more */
	if (fabs(hi[0] - lo[0] - (along_v ? hi[2] + lo[2] : hi[1] + lo[1]) * eps) > 1e-6 ||
	    fabs(hi[1] - lo[1]) > 1e-9 || fabs(hi[2] - lo[2]) > 1e-9)
		fail_msg("step at (%g, %g): f %g/%g, f' %g/%g, %g/%g", u, v,
			 lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]);
}

static void interpolation_continuity(void **state)
{
	char text[4096] = "pitch X\n", line[64];
	struct sh2000_comp_file *f;
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;
	const uint16_t *w;
	double x = -3.0, out[3];
	size_t n;
	int i, j;

	(void)state;
	/* uneven spacing, a curve with all kinds of bends */
	for (i = 0; i < 20; i++, x += 0.7 + 0.3 * sin(i)) {
		snprintf(line, sizeof(line), "%.4f %.6f\n", x,
			 0.002 * sin(x) + 0.0005 * x);
		strcat(text, line);
	}
	strcat(text, "grid Z X Y -1 0.5 6 -2 1 5\n");
	for (j = 0; j < 5; j++)
		for (i = 0; i < 6; i++) {
			snprintf(line, sizeof(line), "%.6f%c", 0.001 * sin(i + 2.0 * j),
				 i == 5 ? '\n' : ' ');
			strcat(text, line);
		}
	f = read_file(text);
	w = sh2000_comp_file_image(f, &n);
	assert_int_equal(sh2000_comp_parse(w, n, &ix, &why), 0);
	assert_int_equal(ix.tables, 2);
	/* the table: through its points, smooth across them, the run-out
	 * (SH2000_COMP_RUNOUT end segments) smooth and then flat */
	{
		const struct sh2000_comp_desc *t = &ix.t[0];
		double p[20], y[20], h0;

		for (i = 0; i < 20; i++) {
			p[i] = (double)(int32_t)((uint32_t)w[t->data + 2 * i] |
						 ((uint32_t)w[t->data + 2 * i + 1] << 16));
			y[i] = sh2000_f32_value((uint32_t)w[t->data + 40 + 2 * i] |
						((uint32_t)w[t->data + 41 + 2 * i] << 16));
			eval_at(w, t, p[i], 0, out);
			assert_true(fabs(out[0] - y[i]) < 1e-6);
			continuous(w, t, p[i], 0, 0);
		}
		h0 = p[1] - p[0];
		continuous(w, t, p[0] - SH2000_COMP_RUNOUT * h0, 0, 0);
		continuous(w, t, p[0] - 0.5 * SH2000_COMP_RUNOUT * h0, 0, 0);
		continuous(w, t, p[19] + SH2000_COMP_RUNOUT * (p[19] - p[18]), 0, 0);
		eval_at(w, t, p[0] - 1e8, 0, out);
		assert_true(out[1] == 0.0);
		eval_at(w, t, p[19] + 1e8, 0, out);
		assert_true(out[1] == 0.0);
	}
	/* the grid: across every line of its cells, both ways, and its edges */
	for (j = -1; j <= 5; j++)
		for (i = -1; i <= 6; i++) {
			double u = -1e5 + i * 0.5e5, v = -2e5 + j * 1e5;

			continuous(w, &ix.t[1], u, v + 0.3e5, 0);
			continuous(w, &ix.t[1], u + 0.2e5, v, 1);
		}
	sh2000_comp_file_free(f);
}

/* ---- on the card ---- */

static struct sh2000 *open_sim(struct sh2000_fw **fw)
{
	struct sh2000 *h = NULL;
	char msg[256];

	if (sh2000_sim_open(&h, NULL, msg, sizeof(msg)) < 0)
		fail_msg("%s", msg);
	assert_int_equal(sh2000_enable(h, 0xfu), 0);
	*fw = sh2000_cardsim_fw(sh2000_sim_card(h));
	return h;
}

static const char good[] =
	"id 0x1234abcd\n"
	"pitch X\n-10 0\n0 0.001\n10 0.0005\n20 0.0007\n";

static void load_and_status(void **state)
{
	struct sh2000_comp_status st;
	struct sh2000_comp_file *f;
	struct sh2000_status s;
	struct sh2000_probe p;
	struct sh2000_fw *fw;
	struct sh2000 *h = open_sim(&fw);
	double off[SH2000_AXES];
	const uint16_t *w;
	size_t n;

	(void)state;
	assert_int_equal(sh2000_comp_status(h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	f = read_file(good);
	w = sh2000_comp_file_image(f, &n);
	assert_int_equal(sh2000_comp_load_file(h, path), 0);
	assert_int_equal(sh2000_comp_status(h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_ACTIVE);
	assert_int_equal(st.tables, 1);
	assert_int_equal(st.id, 0x1234abcdu);
	assert_int_equal(st.sum, sh2000_comp_sum(w, n));
	assert_int_equal(st.generation, 1);
	/* at X = 0 the card holds the scale 1 um (100 counts) further on;
	 * the host still sees the nominal position */
	assert_int_equal(sh2000_sleep_ns(h, 100000000ull), 0);
	sh2000_fw_comp_offset(fw, off);
	assert_true(fabs(off[0] - 100.0) < 0.01);
	assert_int_equal(sh2000_sim_probe(h, &p), 0);
	assert_true(fabs(p.axis[0].actual - 100.0) <= 2.0);
	assert_int_equal(sh2000_poll(h, &s), 0);
	assert_true(llabs(s.axis[0].pos_counts) <= 2);
	assert_int_equal(s.axis[0].cmd_counts, 0);
	assert_int_equal(sh2000_comp_clear(h), 0);
	assert_int_equal(sh2000_comp_status(h, &st), 0);
	assert_int_equal(st.state, SH2000_COMP_NONE);
	assert_int_equal(st.generation, 2);
	sh2000_fw_comp_offset(fw, off);
	assert_true(off[0] == 0.0);
	sh2000_comp_file_free(f);
	sh2000_close(h);
}

/* The card as the good table left it: status words and corrections. */
struct snap {
	struct sh2000_comp_status st;
	double off[SH2000_AXES];
};

static void take(struct sh2000 *h, struct sh2000_fw *fw, struct snap *s)
{
	memset(s, 0, sizeof(*s));
	assert_int_equal(sh2000_comp_status(h, &s->st), 0);
	sh2000_fw_comp_offset(fw, s->off);
}

static void unchanged(struct sh2000 *h, struct sh2000_fw *fw,
		      const struct snap *before)
{
	struct snap now;

	take(h, fw, &now);
	assert_int_equal(now.st.state, before->st.state);
	assert_int_equal(now.st.sum, before->st.sum);
	assert_int_equal(now.st.id, before->st.id);
	assert_int_equal(now.st.generation, before->st.generation);
	assert_memory_equal(now.off, before->off, sizeof(now.off));
}

/* A file the host refuses: FILE:LINE and the words in the message, the
 * same refusal and message from the check alone as from the loader. */
static void host_refuses(struct sh2000 *h, const char *text, unsigned int line,
			 const char *words)
{
	char want[96], checked[512];
	const char *msg;

	write_file(text);
	assert_int_equal(sh2000_comp_check_file(h, path), -SH2000_EPARAM);
	snprintf(checked, sizeof(checked), "%s", sh2000_last_error(h));
	assert_int_equal(sh2000_comp_load_file(h, path), -SH2000_EPARAM);
	msg = sh2000_last_error(h);
	assert_string_equal(msg, checked);
	snprintf(want, sizeof(want), "%s:%u: ", path, line);
	if (!strstr(msg, want) || !strstr(msg, words))
		fail_msg("want '%s' ... '%s' in: %s", want, words, msg);
}

static void host_refusals(void **state)
{
	struct sh2000_fw *fw;
	struct sh2000 *h = open_sim(&fw);
	struct snap before;
	char *big;
	size_t at;
	int i;

	(void)state;
	write_file(good);
	assert_int_equal(sh2000_comp_load_file(h, path), 0);
	take(h, fw, &before);
	host_refuses(h, "pitch X\n0 0\n1 0.001\n1 0.002\n", 4, "not strictly increasing");
	host_refuses(h, "# a step\npitch X\n0 0\n1 0.001\n1.001 0.011\n2 0.011\n", 5,
		     "jump larger than the axis can follow");
	host_refuses(h, "pitch Q\n0 0\n", 1, "an axis is one of");
	host_refuses(h, "pitch X\n0 0\n1 zero\n", 3, "not a list of numbers");
	host_refuses(h, "grid Z X Y 0 1 3 0 1 2\n0 0 0\n", 1, "rows wanted");
	big = malloc(200000);
	assert_non_null(big);
	at = (size_t)sprintf(big, "pitch X\n");
	for (i = 0; i < 5000; i++)
		at += (size_t)sprintf(big + at, "%d 0\n", i);
	host_refuses(h, big, 1, "the card holds 16384");
	free(big);
	unchanged(h, fw, &before);
	/* a good file passes the check and still changes nothing */
	write_file("id 0x77\npitch Y\n0 0\n100 0.001\n");
	assert_int_equal(sh2000_comp_check_file(h, path), 0);
	unchanged(h, fw, &before);
	sh2000_close(h);
}

/* Words to the card as the library would send them, but with a page's
 * check word or the image's sum spoilt on purpose. */
static int raw_load(struct sh2000 *h, const uint16_t *w, size_t n,
		    uint16_t check_xor, uint32_t sum_xor)
{
	uint16_t page[1 + SH2000_COMP_PAGE_WORDS];
	size_t first, k;
	int r;

	r = sh2000_command(h, SH2000_CMD_COMP_BEGIN, 0, 0, (int32_t)n, NULL);
	for (first = 0; !r && first < n; first += k) {
		k = n - first < SH2000_COMP_PAGE_WORDS ? n - first : SH2000_COMP_PAGE_WORDS;
		memcpy(&page[1], &w[first], k * sizeof(w[0]));
		page[0] = sh2000_comp_page_check((uint32_t)first, &page[1],
						 (unsigned int)k) ^ check_xor;
		r = sh2000_ram_write(h, SH2000_W_COMP_PAGE, (unsigned int)k + 1, page);
		if (!r)
			r = sh2000_command(h, SH2000_CMD_COMP_PAGE, 0, (unsigned int)k,
					   (int32_t)first, NULL);
	}
	if (!r)
		r = sh2000_command(h, SH2000_CMD_COMP_COMMIT, 0, 0,
				   (int32_t)(sh2000_comp_sum(w, n) ^ sum_xor), NULL);
	return r;
}

static void card_refusals(void **state)
{
	static const double pt[SH2000_AXES] = { 0 };
	struct sh2000_comp_fault why;
	struct sh2000_comp_file *f;
	struct sh2000_fw *fw;
	struct sh2000 *h = open_sim(&fw);
	double (*pts)[SH2000_AXES];
	struct snap before;
	uint16_t *bad;
	const uint16_t *w;
	size_t n;
	int i;

	(void)state;
	f = read_file("pitch Y\n0 0\n2 0.0001\n4 0.0003\n6 0.0002\n");
	w = sh2000_comp_file_image(f, &n);
	write_file(good);
	assert_int_equal(sh2000_comp_load_file(h, path), 0);
	take(h, fw, &before);
	/* a torn page, a wrong sum */
	assert_int_equal(raw_load(h, w, n, 0x0100, 0), -SH2000_ECMD_CHECKSUM);
	assert_int_equal(raw_load(h, w, n, 0, 0x10), -SH2000_ECMD_CHECKSUM);
	unchanged(h, fw, &before);
	/* the card's own check: positions out of order it was not told */
	bad = malloc(n * sizeof(*bad));
	assert_non_null(bad);
	memcpy(bad, w, n * sizeof(*bad));
	bad[SH2000_COMP_HEADER_WORDS + SH2000_COMP_DESC_WORDS + 4] = 0;	/* point 2 at 0 */
	bad[SH2000_COMP_HEADER_WORDS + SH2000_COMP_DESC_WORDS + 5] = 0;
	assert_int_equal(sh2000_comp_load_image(h, bad, n, &why), -SH2000_ECMD_VALUE);
	assert_int_equal(why.table, 0);
	assert_int_equal(why.point, 2);
	assert_int_equal(why.reason, SH2000_COMP_R_ORDER);
	free(bad);
	unchanged(h, fw, &before);
	/* only at rest: a motion of 0.1 s under way */
	pts = calloc(50, sizeof(*pts));
	assert_non_null(pts);
	for (i = 0; i < 50; i++) {
		memcpy(pts[i], pt, sizeof(pt));
		pts[i][0] = 0.01 * i;
	}
	assert_int_equal(sh2000_push_mm(h, (const double (*)[SH2000_AXES])pts, 50,
					SH2000_PUSH_END), 50);
	assert_int_equal(sh2000_sleep_ns(h, 2000000ull), 0);
	assert_int_equal(sh2000_comp_load_image(h, w, n, NULL), -SH2000_ECMD_BUSY);
	assert_int_equal(sh2000_wait_idle(h, 5000), 0);
	take(h, fw, &before);	/* X moved: its correction with it */
	assert_int_equal(before.st.generation, 1);
	assert_int_equal(sh2000_comp_load_image(h, w, n, NULL), 0);
	free(pts);
	sh2000_comp_file_free(f);
	sh2000_close(h);
}

/* A switch at rest: the correction blends in with no step in position or
 * velocity (each cycle's change no larger than the smoothstep's). */
static void ramp(void *ctx, const struct sh2000_probe *p)
{
	double *o = ctx;	/* last two offsets, largest 1st and 2nd diff */
	double off[SH2000_AXES];

	(void)p;
	sh2000_fw_comp_offset((struct sh2000_fw *)(uintptr_t)o[5], off);
	if (o[4] >= 2) {
		o[2] = fmax(o[2], fabs(off[0] - o[1]));
		o[3] = fmax(o[3], fabs(off[0] - 2 * o[1] + o[0]));
	}
	o[0] = o[1];
	o[1] = off[0];
	o[4]++;
}

static void switch_blends(void **state)
{
	struct sh2000_fw *fw;
	struct sh2000 *h = open_sim(&fw);
	double o[6] = { 0 }, n = SH2000_COMP_BLEND_MS * 10.0;	/* cycles */

	(void)state;
	o[5] = (double)(uintptr_t)fw;
	write_file(good);
	assert_int_equal(sh2000_sim_set_observer(h, ramp, o), 0);
	assert_int_equal(sh2000_comp_load_file(h, path), 0);
	assert_int_equal(sh2000_sleep_ns(h, 10000000ull), 0);
	assert_int_equal(sh2000_sim_set_observer(h, NULL, NULL), 0);
	assert_true(fabs(o[1] - 100.0) < 0.01);
	/* smoothstep: slope 1.5 / n, second difference 6 / n^2, of 100 */
	assert_true(o[2] <= 1.5 * 100.0 / n * 1.01);
	assert_true(o[3] <= 6.0 * 100.0 / (n * n) * 1.01);
	sh2000_close(h);
}

/* ---- beside a gantry pair (protocol 1.7) ---- */

/* A table that corrects one side of a gantry pair is what that side is
 * meant to do: the card's skew is the difference of the loops' errors,
 * each with its correction, so 1 um (100 counts) of Y's pitch under a
 * skew limit of 50 counts neither trips SKEW nor is fought by the
 * coupling. (Taken from the nominal set-points, the skew read 100 counts
 * and latched SKEW on both sides.) */
static void gantry_side_table(void **state)
{
	const int G = SH2000_GLOBAL;
	struct sh2000_status st;
	struct sh2000_fw *fw;
	struct sh2000 *h = open_sim(&fw);
	double off[SH2000_AXES];

	(void)state;
	assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_PAIR, 6), 0);
	assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_KP, 5.0), 0);
	assert_int_equal(sh2000_param_set(h, G, SH2000_GP_GANTRY_SKEW_LIMIT,
					  50), 0);
	write_file("pitch Y\n-10 0.001\n0 0.001\n10 0.001\n");
	assert_int_equal(sh2000_comp_load_file(h, path), 0);
	assert_int_equal(sh2000_sleep_ns(h, 100000000ull), 0);
	sh2000_fw_comp_offset(fw, off);
	assert_true(fabs(off[1] - 100.0) < 0.01 && off[2] == 0.0);
	assert_int_equal(sh2000_poll(h, &st), 0);
	assert_int_equal(st.axis[1].faults, 0);
	assert_int_equal(st.axis[2].faults, 0);
	assert_int_equal(st.card_faults, 0);
	assert_true(llabs(st.axis[1].pos_counts) <= 2 &&
		    llabs(st.axis[2].pos_counts) <= 2);
	sh2000_close(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(interpolation_continuity),
		cmocka_unit_test(load_and_status),
		cmocka_unit_test(host_refusals),
		cmocka_unit_test(card_refusals),
		cmocka_unit_test(switch_blends),
		cmocka_unit_test(gantry_side_table),
	};
	int fd, r;

	snprintf(path, sizeof(path), "/tmp/test-comp-XXXXXX");
	fd = mkstemp(path);
	if (fd < 0)
		return 1;
	close(fd);
	r = cmocka_run_group_tests(tests, NULL, NULL);
	unlink(path);
	return r;
}
