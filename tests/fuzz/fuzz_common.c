// SPDX-License-Identifier: MIT
/* The checks the program harnesses share (fuzz.h). */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

void fz_fail(const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "fuzz: ");
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, "\n");
	abort();
}

static int finite_point(const double x[SH2000_AXES])
{
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (!isfinite(x[a]))
			return 0;
	return 1;
}

/* An arc the geometry resolves: within SH2000_ARC_MAX_MM, and its sweep
 * leads from its start to its end (to the rounding of its angles: a sweep
 * that rounded to nothing once made a whole circle). */
static void check_arc_resolved(size_t i, const struct sh2000_prog_block *b)
{
	const struct sh2000_arc *a = &b->u.arc;
	double m = fmax(fmax(fabs(a->centre[0]), fabs(a->centre[1])),
			fmax(a->r0, a->r1)), x[SH2000_AXES], d = 0, allow;

	if (m > SH2000_ARC_MAX_MM)
		fz_fail("block %zu: arc radius or centre %g mm beyond %g mm", i,
			m, SH2000_ARC_MAX_MM);
	sh2000_arc_point(a, b->start, b->end, 1.0, x);
	for (unsigned int k = 0; k < SH2000_AXES; k++)
		d += (x[k] - b->end[k]) * (x[k] - b->end[k]);
	allow = 1e-6 + 16 * DBL_EPSILON * 2 * m * (M_PI + fabs(a->sweep));
	/* a full circle ends where it starts: rs274's canonical output may
	 * print its end up to both prints' rounding (4 decimals of inches)
	 * away from its start (docs/programs.md) */
	if (fabs(fabs(a->sweep) - 2 * M_PI * a->turns) < 1e-9)
		allow += M_SQRT2 * 2 * 0.5e-4 * 25.4;
	if (sqrt(d) > allow)
		fz_fail("block %zu: the arc's sweep %g ends %g mm from its end (allowed %g)",
			i, a->sweep, sqrt(d), allow);
}

static void check_arc(size_t i, const struct sh2000_prog_block *b)
{
	const struct sh2000_arc *a = &b->u.arc;

	if (!(a->r0 > 0 && isfinite(a->r0)) ||
	    !(a->fit_radius > 0 && isfinite(a->fit_radius)) ||
	    !isfinite(a->r1) || !isfinite(a->sweep) || a->sweep == 0)
		fz_fail("block %zu: arc radius %g fit %g end %g sweep %g", i,
			a->r0, a->fit_radius, a->r1, a->sweep);
	if (a->turns < 1 || (a->ccw ? a->sweep < 0 : a->sweep > 0))
		fz_fail("block %zu: arc turns %u ccw %d sweep %g", i, a->turns,
			a->ccw, a->sweep);
	for (unsigned int k = 0; k < 2; k++)
		if (!isfinite(a->centre[k]) || !isfinite(a->fit_centre[k]))
			fz_fail("block %zu: arc centre not finite", i);
	check_arc_resolved(i, b);
}

/* The reader must hand out only curves the geometry module accepts. */
static void check_nurbs(size_t i, const struct sh2000_prog_block *b)
{
	char msg[256];

	if (sh2000_nurbs_check(&b->u.nurbs, msg, sizeof(msg)))
		fz_fail("block %zu: NURBS the reader accepted: %s", i, msg);
}

static void check_block(size_t i, const struct sh2000_prog_block *b,
			const double *prev_end)
{
	if (b->kind < SH2000_PROG_RAPID || b->kind > SH2000_PROG_PATH_MODE)
		fz_fail("block %zu: kind %d", i, (int)b->kind);
	if (!finite_point(b->start) || !finite_point(b->end))
		fz_fail("block %zu (%s): start or end not finite", i,
			sh2000_prog_kind_name(b->kind));
	if (b->pos.line == 0)
		fz_fail("block %zu: no line", i);
	if (prev_end && memcmp(prev_end, b->start, sizeof(b->start)))
		fz_fail("block %zu (%s): starts at (%g %g %g %g), the block before ended at (%g %g %g %g)",
			i, sh2000_prog_kind_name(b->kind), b->start[0],
			b->start[1], b->start[2], b->start[3], prev_end[0],
			prev_end[1], prev_end[2], prev_end[3]);
	switch (b->kind) {
	case SH2000_PROG_LINE:
	case SH2000_PROG_ARC:
	case SH2000_PROG_NURBS:
		if (!(b->feed > 0 && isfinite(b->feed)))
			fz_fail("block %zu (%s): feed %g", i,
				sh2000_prog_kind_name(b->kind), b->feed);
		break;
	case SH2000_PROG_FEED:	/* F0 is a feed: moves with it are not */
		if (!(b->feed >= 0 && isfinite(b->feed)))
			fz_fail("block %zu: feed %g", i, b->feed);
		break;
	case SH2000_PROG_DWELL:
		if (!(b->u.dwell_s >= 0 && isfinite(b->u.dwell_s)))
			fz_fail("block %zu: dwell %g", i, b->u.dwell_s);
		break;
	default:
		break;
	}
	if (b->kind == SH2000_PROG_ARC)
		check_arc(i, b);
	if (b->kind == SH2000_PROG_NURBS)
		check_nurbs(i, b);
}

static void check_diags(const struct sh2000_prog_diags *d, const char *text,
			size_t len)
{
	unsigned int lines = 1;
	size_t errors = 0;
	char buf[512];

	for (size_t i = 0; i < len; i++)
		lines += text[i] == '\n';
	for (size_t i = 0; i < d->count; i++) {
		const struct sh2000_prog_diag *g = &d->items[i];

		if (!g->message || !g->message[0])
			fz_fail("diagnostic %zu has no message", i);
		if (g->pos.line > lines)
			fz_fail("diagnostic %zu at line %u of a %u-line text: %s",
				i, g->pos.line, lines, g->message);
		if (sh2000_prog_diag_format(g, buf, sizeof(buf)) <= 0)
			fz_fail("diagnostic %zu does not format", i);
		errors += g->severity == SH2000_PROG_ERROR;
	}
	if (errors != d->errors || d->errors + d->warnings != d->count)
		fz_fail("diagnostics: %zu items, %zu errors counted (%zu found), %zu warnings",
			d->count, d->errors, errors, d->warnings);
}

void fz_check_program(int r, const struct sh2000_program *p,
		      const struct sh2000_prog_diags *d, const char *text,
		      size_t len)
{
	static const double origin[SH2000_AXES];	/* the default start */
	const double *prev = origin;

	check_diags(d, text, len);
	if (r != 0 && r != -SH2000_EPROGRAM && r != -ENOMEM)
		fz_fail("reader returned %d (%s)", r, sh2000_strerror(r));
	if (r == -SH2000_EPROGRAM && !d->errors)
		fz_fail("reader failed without an error in the diagnostics");
	if (r == 0 && d->errors)
		fz_fail("reader succeeded with %zu errors", d->errors);
	if (r < 0) {
		if (p->count)
			fz_fail("reader failed and left %zu blocks", p->count);
		return;
	}
	for (size_t i = 0; i < p->count; i++) {
		check_block(i, &p->blocks[i], prev);
		prev = p->blocks[i].end;
	}
}
