/* SPDX-License-Identifier: MIT */
/* The program representation, diagnostics, file reading and geometry. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "prog_internal.h"

const char *sh2000_prog_strerror(int code)
{
	return sh2000_strerror(code);
}

/* ---- diagnostics ---------------------------------------------------- */

void sh2000_prog_diags_init(struct sh2000_prog_diags *d)
{
	memset(d, 0, sizeof(*d));
}

void sh2000_prog_diags_free(struct sh2000_prog_diags *d)
{
	for (size_t i = 0; i < d->count; i++) {
		free((char *)d->items[i].pos.file);
		free(d->items[i].message);
	}
	free(d->items);
	memset(d, 0, sizeof(*d));
}

int sh2000_prog_diag_format(const struct sh2000_prog_diag *g, char *buf,
			    size_t size)
{
	const char *sev = g->severity == SH2000_PROG_ERROR ? "error" : "warning";

	if (g->pos.line == 0)
		return snprintf(buf, size, "%s: %s: %s", g->pos.file, sev,
				g->message);
	return snprintf(buf, size, "%s:%u:%u: %s: %s", g->pos.file,
			g->pos.line, g->pos.column, sev, g->message);
}

int sh2000_prog_diags_print(const struct sh2000_prog_diags *d, void *f)
{
	FILE *out = f;

	for (size_t i = 0; i < d->count; i++) {
		const struct sh2000_prog_diag *g = &d->items[i];
		const char *sev = g->severity == SH2000_PROG_ERROR ? "error" :
				  "warning";
		int n = g->pos.line ?
			fprintf(out, "%s:%u:%u: %s: %s\n", g->pos.file,
				g->pos.line, g->pos.column, sev, g->message) :
			fprintf(out, "%s: %s: %s\n", g->pos.file, sev,
				g->message);

		if (n < 0)
			return -EIO;
	}
	return (int)d->count;
}

static int diag_vadd(struct prog_ctx *c, enum sh2000_prog_severity sev,
		     enum sh2000_prog_diag_code code, unsigned int line,
		     unsigned int col, const char *fmt, va_list ap)
{
	struct sh2000_prog_diags *d = c->diags;
	struct sh2000_prog_diag *g;
	va_list ap2;
	int n;

	if (d->count == d->cap) {
		size_t cap = d->cap ? d->cap * 2 : 16;
		void *p = realloc(d->items, cap * sizeof(*d->items));

		if (!p)
			goto oom;
		d->items = p;
		d->cap = cap;
	}
	g = &d->items[d->count];
	memset(g, 0, sizeof(*g));
	g->severity = sev;
	g->code = code;
	g->pos.line = line;
	g->pos.column = col;
	g->pos.file = strdup(c->name);
	va_copy(ap2, ap);
	n = vsnprintf(NULL, 0, fmt, ap2);
	va_end(ap2);
	g->message = n >= 0 ? malloc((size_t)n + 1) : NULL;
	if (!g->pos.file || !g->message) {
		free((char *)g->pos.file);
		free(g->message);
		goto oom;
	}
	vsnprintf(g->message, (size_t)n + 1, fmt, ap);
	d->count++;
	if (sev == SH2000_PROG_ERROR)
		d->errors++;
	else
		d->warnings++;
	return 0;
oom:
	c->oom = true;
	c->stop = true;
	return -ENOMEM;
}

static int diag_add(struct prog_ctx *c, enum sh2000_prog_severity sev,
		    enum sh2000_prog_diag_code code, unsigned int line,
		    unsigned int col, const char *fmt, ...)
	__attribute__((format(printf, 6, 7)));
static int diag_add(struct prog_ctx *c, enum sh2000_prog_severity sev,
		    enum sh2000_prog_diag_code code, unsigned int line,
		    unsigned int col, const char *fmt, ...)
{
	va_list ap;
	int ret;

	va_start(ap, fmt);
	ret = diag_vadd(c, sev, code, line, col, fmt, ap);
	va_end(ap);
	return ret;
}

int prog_diag(struct prog_ctx *c, enum sh2000_prog_severity sev,
	      enum sh2000_prog_diag_code code, unsigned int line,
	      unsigned int col, const char *fmt, ...)
{
	va_list ap;
	int ret;

	if (c->stop)
		return sev == SH2000_PROG_ERROR ? -SH2000_PROG_EINVALID : 0;
	va_start(ap, fmt);
	ret = diag_vadd(c, sev, code, line, col, fmt, ap);
	va_end(ap);
	if (ret)
		return ret;
	if (sev != SH2000_PROG_ERROR)
		return 0;
	if (++c->errors >= c->opt.max_errors) {
		c->stop = true;
		diag_add(c, SH2000_PROG_ERROR, SH2000_PD_LIMIT, line, col,
			 "too many errors (%u), reading stopped", c->errors);
	}
	return -SH2000_PROG_EINVALID;
}

int prog_warn_once(struct prog_ctx *c, unsigned int kind,
		   enum sh2000_prog_diag_code code, unsigned int line,
		   unsigned int col, const char *fmt, ...)
{
	va_list ap;
	int ret;

	if ((c->warned & kind) || c->stop)
		return 0;
	c->warned |= kind;
	va_start(ap, fmt);
	ret = diag_vadd(c, SH2000_PROG_WARNING, code, line, col, fmt, ap);
	va_end(ap);
	return ret;
}

/* ---- programs -------------------------------------------------------- */

void sh2000_program_init(struct sh2000_program *p)
{
	memset(p, 0, sizeof(*p));
}

void sh2000_program_free(struct sh2000_program *p)
{
	for (size_t i = 0; i < p->count; i++) {
		struct sh2000_prog_block *b = &p->blocks[i];

		if (b->kind == SH2000_PROG_NURBS) {
			free(b->u.nurbs.points);
			free(b->u.nurbs.weights);
			free(b->u.nurbs.knots);
		}
	}
	free(p->blocks);
	free(p->file);
	memset(p, 0, sizeof(*p));
}

struct sh2000_prog_block *prog_push(struct prog_ctx *c,
				    enum sh2000_prog_kind kind,
				    unsigned int line, unsigned int col)
{
	struct sh2000_program *p = c->prog;
	struct sh2000_prog_block *b;

	if (p->count == p->cap) {
		size_t cap = p->cap ? p->cap * 2 : 64;
		void *n = realloc(p->blocks, cap * sizeof(*p->blocks));

		if (!n) {
			c->oom = true;
			c->stop = true;
			return NULL;
		}
		p->blocks = n;
		p->cap = cap;
	}
	b = &p->blocks[p->count++];
	memset(b, 0, sizeof(*b));
	b->kind = kind;
	b->pos.file = p->file;
	b->pos.line = line;
	b->pos.column = col;
	memcpy(b->start, c->pos, sizeof(b->start));
	memcpy(b->end, c->pos, sizeof(b->end));
	return b;
}

void sh2000_prog_options_default(struct sh2000_prog_options *o)
{
	memset(o, 0, sizeof(*o));
	o->max_errors = 20;
}

enum sh2000_prog_format sh2000_prog_format_guess(const char *name)
{
	static const struct {
		const char *ext;
		enum sh2000_prog_format f;
	} map[] = {
		{ "ngc", SH2000_PROG_GCODE }, { "nc", SH2000_PROG_GCODE },
		{ "gcode", SH2000_PROG_GCODE }, { "g", SH2000_PROG_GCODE },
		{ "tap", SH2000_PROG_GCODE }, { "cnc", SH2000_PROG_GCODE },
		{ "canon", SH2000_PROG_CANON }, { "csv", SH2000_PROG_CSV },
		{ "json", SH2000_PROG_NURBS_JSON },
	};
	const char *dot = name ? strrchr(name, '.') : NULL;

	if (!dot || strchr(dot, '/'))
		return SH2000_PROG_AUTO;
	for (size_t i = 0; i < sizeof(map) / sizeof(map[0]); i++)
		if (!strcasecmp(dot + 1, map[i].ext))
			return map[i].f;
	return SH2000_PROG_AUTO;
}

const char *sh2000_prog_format_name(enum sh2000_prog_format f)
{
	switch (f) {
	case SH2000_PROG_GCODE: return "G-code";
	case SH2000_PROG_CANON: return "rs274 canonical commands";
	case SH2000_PROG_CSV: return "CSV point list";
	case SH2000_PROG_NURBS_JSON: return "JSON NURBS";
	default: return "auto";
	}
}

const char *sh2000_prog_kind_name(enum sh2000_prog_kind k)
{
	switch (k) {
	case SH2000_PROG_RAPID: return "rapid";
	case SH2000_PROG_LINE: return "line";
	case SH2000_PROG_ARC: return "arc";
	case SH2000_PROG_NURBS: return "nurbs";
	case SH2000_PROG_FEED: return "feed";
	case SH2000_PROG_DWELL: return "dwell";
	case SH2000_PROG_PAUSE: return "pause";
	case SH2000_PROG_END: return "end";
	}
	return "?";
}

size_t prog_next_line(const char *text, size_t len, size_t off, size_t *n)
{
	size_t e = off;

	while (e < len && text[e] != '\n')
		e++;
	*n = e - off;
	if (*n && text[off + *n - 1] == '\r')
		(*n)--;
	return e < len ? e + 1 : len;
}

int sh2000_program_read(struct sh2000_program *prog,
			enum sh2000_prog_format fmt, const char *name,
			const char *text, size_t len,
			const struct sh2000_prog_options *opt,
			struct sh2000_prog_diags *diags)
{
	struct prog_ctx c;
	int ret;

	sh2000_program_free(prog);
	if (!name)
		name = "<program>";
	if (fmt == SH2000_PROG_AUTO)
		fmt = sh2000_prog_format_guess(name);
	memset(&c, 0, sizeof(c));
	c.prog = prog;
	c.diags = diags;
	c.name = name;
	if (opt)
		c.opt = *opt;
	else
		sh2000_prog_options_default(&c.opt);
	if (c.opt.max_errors == 0)
		c.opt.max_errors = 20;
	memcpy(c.pos, c.opt.start, sizeof(c.pos));
	if (fmt == SH2000_PROG_AUTO) {
		prog_err(&c, SH2000_PD_UNKNOWN, 0, 0,
			 "cannot tell the program format from the name (use .ngc, .nc, .gcode, .canon, .csv or .json, or name the format)");
		return -SH2000_PROG_EFORMAT;
	}
	prog->file = strdup(name);
	if (!prog->file)
		return -ENOMEM;
	for (unsigned int i = 0; i < SH2000_AXES; i++)
		if (!isfinite(c.opt.start[i]))
			prog_err(&c, SH2000_PD_RANGE, 0, 0,
				 "start position of axis %c is not finite",
				 "XYZA"[i]);
	if (c.errors == 0) {
		switch (fmt) {
		case SH2000_PROG_GCODE:
			ret = prog_read_gcode(&c, text, len);
			break;
		case SH2000_PROG_CANON:
			ret = prog_read_canon(&c, text, len);
			break;
		case SH2000_PROG_CSV:
			ret = prog_read_csv(&c, text, len);
			break;
		case SH2000_PROG_NURBS_JSON:
			ret = prog_read_nurbs_json(&c, text, len);
			break;
		default:
			ret = -SH2000_PROG_EFORMAT;
			break;
		}
		(void)ret;
	}
	if (c.oom) {
		sh2000_program_free(prog);
		return -ENOMEM;
	}
	if (c.errors) {
		sh2000_program_free(prog);
		return -SH2000_PROG_EINVALID;
	}
	return 0;
}

int sh2000_program_read_file(struct sh2000_program *prog,
			     enum sh2000_prog_format fmt, const char *path,
			     const struct sh2000_prog_options *opt,
			     struct sh2000_prog_diags *diags)
{
	bool is_stdin = !strcmp(path, "-");
	const char *name = is_stdin ? "<stdin>" : path;
	FILE *f = is_stdin ? stdin : fopen(path, "rb");
	char *buf = NULL;
	size_t len = 0, cap = 0;
	int ret = 0;

	sh2000_program_free(prog);
	if (!f) {
		ret = -errno;
		goto fail;
	}
	for (;;) {
		size_t n;

		if (len == cap) {
			size_t ncap = cap ? cap * 2 : 65536;
			char *nb = realloc(buf, ncap);

			if (!nb) {
				ret = -ENOMEM;
				break;
			}
			buf = nb;
			cap = ncap;
		}
		n = fread(buf + len, 1, cap - len, f);
		len += n;
		if (n == 0) {
			if (ferror(f))
				ret = errno ? -errno : -EIO;
			break;
		}
	}
	if (!is_stdin)
		fclose(f);
	if (ret)
		goto fail;
	if (fmt == SH2000_PROG_AUTO && is_stdin)
		fmt = SH2000_PROG_GCODE;
	ret = sh2000_program_read(prog, fmt, name, buf ? buf : "", len, opt,
				  diags);
	free(buf);
	return ret;
fail:
	free(buf);
	{
		struct prog_ctx c;

		memset(&c, 0, sizeof(c));
		c.diags = diags;
		c.name = name;
		c.opt.max_errors = 1000;
		prog_err(&c, SH2000_PD_SYNTAX, 0, 0, "cannot read: %s",
			 strerror(-ret));
	}
	return ret;
}

/* ---- arcs -------------------------------------------------------------- */

void prog_plane_axes(enum sh2000_prog_plane plane, unsigned int *a1,
		     unsigned int *a2, unsigned int *an)
{
	switch (plane) {
	case SH2000_PROG_XZ:
		*a1 = SH2000_PROG_Z; *a2 = SH2000_PROG_X; *an = SH2000_PROG_Y;
		break;
	case SH2000_PROG_YZ:
		*a1 = SH2000_PROG_Y; *a2 = SH2000_PROG_Z; *an = SH2000_PROG_X;
		break;
	default:
		*a1 = SH2000_PROG_X; *a2 = SH2000_PROG_Y; *an = SH2000_PROG_Z;
		break;
	}
}

int prog_arc_fill(struct prog_ctx *c, struct sh2000_prog_block *b,
		  enum sh2000_prog_plane plane, double c1, double c2,
		  bool ccw, unsigned int turns, double tol_mm, double same_mm,
		  unsigned int line, unsigned int col)
{
	struct sh2000_prog_arc *a = &b->u.arc;
	double s1, s2, e1, e2, r1, r2, abs_err, rel_err, a0, a1, d;

	a->plane = plane;
	prog_plane_axes(plane, &a->axis1, &a->axis2, &a->axisn);
	s1 = b->start[a->axis1];
	s2 = b->start[a->axis2];
	e1 = b->end[a->axis1];
	e2 = b->end[a->axis2];
	r1 = hypot(s1 - c1, s2 - c2);
	r2 = hypot(e1 - c1, e2 - c2);
	if (!isfinite(r1) || !isfinite(r2))
		return prog_err(c, SH2000_PD_RANGE, line, col,
				"arc geometry is not finite");
	if (r1 < PROG_RADIUS_TOL_MM || r2 < PROG_RADIUS_TOL_MM)
		return prog_err(c, SH2000_PD_ARC, line, col,
				"zero-radius arc: r1=%.4f mm r2=%.4f mm", r1, r2);
	abs_err = fabs(r1 - r2);
	rel_err = abs_err / fmax(r1, r2);
	/* LinuxCNC 2.9 (checked against Debian's rs274): an error past 100
	 * times the tolerance, or past the tolerance and 0.1 % at once */
	if (abs_err > 100 * tol_mm ||
	    (abs_err > tol_mm && rel_err > PROG_SPIRAL_REL_TOL))
		return prog_err(c, SH2000_PD_ARC, line, col,
				"radius to end of arc differs from radius to start: start=(%c%.4f,%c%.4f) centre=(%c%.4f,%c%.4f) end=(%c%.4f,%c%.4f) r1=%.4f r2=%.4f mm (allowed: %.4f mm, or %.1f%% of the radius up to %.4f mm)",
				"XYZA"[a->axis1], s1, "XYZA"[a->axis2], s2,
				"XYZA"[a->axis1], c1, "XYZA"[a->axis2], c2,
				"XYZA"[a->axis1], e1, "XYZA"[a->axis2], e2,
				r1, r2, tol_mm, PROG_SPIRAL_REL_TOL * 100, 100 * tol_mm);
	a->centre[a->axis1] = c1;
	a->centre[a->axis2] = c2;
	a->centre[a->axisn] = b->start[a->axisn];
	a->ccw = ccw;
	a->turns = turns;
	a->radius = r1;
	a->end_radius = r2;
	memcpy(a->fit_centre, a->centre, sizeof(a->fit_centre));
	a->fit_radius = r1;
	if (hypot(e1 - s1, e2 - s2) >= fmax(same_mm, 1e-9)) {
		double len = hypot(e1 - s1, e2 - s2);
		double u1 = -(e2 - s2) / len, u2 = (e1 - s1) / len;
		double m1 = (s1 + e1) / 2, m2 = (s2 + e2) / 2;
		double t = (c1 - m1) * u1 + (c2 - m2) * u2;

		a->fit_centre[a->axis1] = m1 + t * u1;
		a->fit_centre[a->axis2] = m2 + t * u2;
		a->fit_radius = hypot(s1 - a->fit_centre[a->axis1],
				      s2 - a->fit_centre[a->axis2]);
	}
	a0 = atan2(s2 - c2, s1 - c1);
	a1 = atan2(e2 - c2, e1 - c1);
	d = a1 - a0;
	/* an end equal to the start (to rounding) is a full circle */
	if (hypot(e1 - s1, e2 - s2) < fmax(same_mm, 1e-9))
		d = 0;
	if (ccw) {
		while (d <= 0)
			d += 2 * M_PI;
		while (d > 2 * M_PI)
			d -= 2 * M_PI;
		d += 2 * M_PI * (turns - 1);
	} else {
		while (d >= 0)
			d -= 2 * M_PI;
		while (d < -2 * M_PI)
			d += 2 * M_PI;
		d -= 2 * M_PI * (turns - 1);
	}
	a->sweep = d;
	return 0;
}

int prog_arc_centre_r(struct prog_ctx *c, double s1, double s2, double e1,
		      double e2, double r, bool ccw, double *c1, double *c2,
		      unsigned int line, unsigned int col)
{
	double abs_r = fabs(r), mid1, mid2, half, theta, offset;

	if (e1 == s1 && e2 == s2)
		return prog_err(c, SH2000_PD_ARC, line, col,
				"R-format arc ends where it starts: the centre is undefined (use I/J/K for a full circle)");
	mid1 = (e1 + s1) / 2;
	mid2 = (e2 + s2) / 2;
	half = hypot(mid1 - e1, mid2 - e2);
	if (half - abs_r > PROG_RADIUS_TOL_MM)
		return prog_err(c, SH2000_PD_ARC, line, col,
				"arc radius %.4f mm too small to reach the end point (half chord %.4f mm)",
				abs_r, half);
	if (half / abs_r > 1 - 1e-12)
		half = abs_r;
	/* G2 with R>0 or G3 with R<0 has its centre right of the chord */
	if ((!ccw && r > 0) || (ccw && r < 0))
		theta = atan2(e2 - s2, e1 - s1) - M_PI_2;
	else
		theta = atan2(e2 - s2, e1 - s1) + M_PI_2;
	offset = abs_r * cos(asin(half / abs_r));
	*c1 = mid1 + offset * cos(theta);
	*c2 = mid2 + offset * sin(theta);
	return 0;
}

/* ---- NURBS ------------------------------------------------------------- */

int prog_nurbs_check(struct prog_ctx *c, const struct sh2000_prog_nurbs *n,
		     unsigned int line, unsigned int col)
{
	size_t nk = n->npoints + n->degree + 1, mult = 1;

	if (n->degree < 1 || n->degree > PROG_MAX_DEGREE)
		return prog_err(c, SH2000_PD_NURBS, line, col,
				"degree: %u is outside 1..%d", n->degree,
				PROG_MAX_DEGREE);
	if (n->npoints < (size_t)n->degree + 1)
		return prog_err(c, SH2000_PD_NURBS, line, col,
				"points: %zu control points, a degree %u curve needs at least %u",
				n->npoints, n->degree, n->degree + 1);
	for (size_t i = 0; i < n->npoints; i++) {
		if (!(n->weights[i] > 0) || !isfinite(n->weights[i]))
			return prog_err(c, SH2000_PD_NURBS, line, col,
					"weights[%zu]: %g is not a positive finite weight",
					i, n->weights[i]);
		for (unsigned int a = 0; a < SH2000_AXES; a++)
			if (!isfinite(n->points[i][a]))
				return prog_err(c, SH2000_PD_RANGE, line, col,
						"points[%zu][%d]: not finite", i, a);
	}
	for (size_t i = 0; i < nk; i++) {
		if (!isfinite(n->knots[i]))
			return prog_err(c, SH2000_PD_RANGE, line, col,
					"knots[%zu]: not finite", i);
		if (i == 0)
			continue;
		if (n->knots[i] < n->knots[i - 1])
			return prog_err(c, SH2000_PD_NURBS, line, col,
					"knots[%zu]: %g is less than knots[%zu] = %g (knots must not decrease)",
					i, n->knots[i], i - 1, n->knots[i - 1]);
		mult = n->knots[i] == n->knots[i - 1] ? mult + 1 : 1;
		/* inside the domain a knot repeated more than degree times
		 * breaks the curve apart */
		if (mult > n->degree && i > n->degree && i < n->npoints)
			return prog_err(c, SH2000_PD_NURBS, line, col,
					"knots[%zu]: value %g repeated %zu times inside the curve's domain; at most degree (%u) times or the curve breaks",
					i, n->knots[i], mult, n->degree);
	}
	if (!(n->knots[n->degree] < n->knots[n->npoints]))
		return prog_err(c, SH2000_PD_NURBS, line, col,
				"knots: the domain knots[%u]..knots[%zu] is empty",
				n->degree, n->npoints);
	return 0;
}

void sh2000_prog_nurbs_eval(const struct sh2000_prog_nurbs *n, double u,
			    double out[SH2000_AXES])
{
	const double *U = n->knots;
	unsigned int p = n->degree;
	size_t span, last = n->npoints - 1;
	double N[PROG_MAX_DEGREE + 1], left[PROG_MAX_DEGREE + 1],
	       right[PROG_MAX_DEGREE + 1], w = 0;

	if (u < U[p])
		u = U[p];
	if (u > U[n->npoints])
		u = U[n->npoints];
	/* the span [U[span], U[span+1]) holding u; the last non-empty one at
	 * the domain's end */
	span = p;
	for (size_t i = p; i <= last; i++)
		if (U[i] <= u && U[i] < U[i + 1])
			span = i;
	N[0] = 1;
	for (unsigned int j = 1; j <= p; j++) {
		double saved = 0;

		left[j] = u - U[span + 1 - j];
		right[j] = U[span + j] - u;
		for (unsigned int r = 0; r < j; r++) {
			double t = N[r] / (right[r + 1] + left[j - r]);

			N[r] = saved + right[r + 1] * t;
			saved = left[j - r] * t;
		}
		N[j] = saved;
	}
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		out[a] = 0;
	for (unsigned int r = 0; r <= p; r++) {
		size_t k = span - p + r;
		double nw = N[r] * n->weights[k];

		w += nw;
		for (unsigned int a = 0; a < SH2000_AXES; a++)
			out[a] += nw * n->points[k][a];
	}
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		out[a] /= w;
}

int sh2000_prog_block_point(const struct sh2000_prog_block *b, double s,
			    double out[SH2000_AXES])
{
	switch (b->kind) {
	case SH2000_PROG_RAPID:
	case SH2000_PROG_LINE:
		for (unsigned int a = 0; a < SH2000_AXES; a++)
			out[a] = b->start[a] + s * (b->end[a] - b->start[a]);
		return 0;
	case SH2000_PROG_ARC: {
		const struct sh2000_prog_arc *a = &b->u.arc;
		double a0 = atan2(b->start[a->axis2] - a->centre[a->axis2],
				  b->start[a->axis1] - a->centre[a->axis1]);
		double th = a0 + s * a->sweep;
		double r = a->radius + s * (a->end_radius - a->radius);

		for (unsigned int i = 0; i < SH2000_AXES; i++)
			out[i] = b->start[i] + s * (b->end[i] - b->start[i]);
		out[a->axis1] = a->centre[a->axis1] + r * cos(th);
		out[a->axis2] = a->centre[a->axis2] + r * sin(th);
		return 0;
	}
	case SH2000_PROG_NURBS: {
		const struct sh2000_prog_nurbs *n = &b->u.nurbs;
		double u0 = n->knots[n->degree], u1 = n->knots[n->npoints];

		sh2000_prog_nurbs_eval(n, u0 + s * (u1 - u0), out);
		return 0;
	}
	default:
		return -EINVAL;
	}
}
