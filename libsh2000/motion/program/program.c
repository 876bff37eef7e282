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

	if (c->quiet)
		return 0;
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
	if (c->replay && sev != SH2000_PROG_ERROR)
		return 0;	/* given on the first pass */
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

	if ((c->warned & kind) || c->stop || c->replay)
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
	prog_clear_blocks(p);
	free(p->blocks);
	free(p->file);
	memset(p, 0, sizeof(*p));
}

void prog_clear_blocks(struct sh2000_program *p)
{
	for (size_t i = 0; i < p->count; i++) {
		struct sh2000_prog_block *b = &p->blocks[i];

		if (b->kind == SH2000_PROG_NURBS) {
			/* the program's own arrays behind the view */
			free((void *)b->u.nurbs.points);
			free((void *)b->u.nurbs.weights);
			free((void *)b->u.nurbs.knots);
		}
	}
	p->count = 0;
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
	case SH2000_PROG_PATH_MODE: return "path mode";
	}
	return "?";
}

int sh2000_program_read(struct sh2000_program *prog,
			enum sh2000_prog_format fmt, const char *name,
			const char *text, size_t len,
			const struct sh2000_prog_options *opt,
			struct sh2000_prog_diags *diags)
{
	struct sh2000_prog_reader *r;
	int ret;

	sh2000_program_free(prog);
	ret = sh2000_prog_reader_open_text(&r, fmt, name, text, len, opt,
					   diags);
	if (!ret)
		ret = prog_read_all(r, prog);
	sh2000_prog_reader_close(r);
	if (ret)
		sh2000_program_free(prog);
	return ret;
}

int sh2000_program_read_file(struct sh2000_program *prog,
			     enum sh2000_prog_format fmt, const char *path,
			     const struct sh2000_prog_options *opt,
			     struct sh2000_prog_diags *diags)
{
	struct sh2000_prog_reader *r;
	int ret;

	sh2000_program_free(prog);
	ret = sh2000_prog_reader_open(&r, fmt, path, opt, diags);
	if (!ret)
		ret = prog_read_all(r, prog);
	sh2000_prog_reader_close(r);
	if (ret)
		sh2000_program_free(prog);
	return ret;
}

/* ---- arcs -------------------------------------------------------------- */

int prog_arc_fill(struct prog_ctx *c, struct sh2000_prog_block *b,
		  enum sh2000_plane plane, double c1, double c2,
		  bool ccw, unsigned int turns, double tol_mm, double same_mm,
		  unsigned int line, unsigned int col)
{
	double centre[2] = { c1, c2 };
	char m[400];
	int r;

	r = sh2000_arc_resolve(&b->u.arc, plane, b->start, b->end, centre, ccw,
			       turns, tol_mm, same_mm, m, sizeof(m));
	if (r)
		return prog_err(c, r == -ERANGE ? SH2000_PD_RANGE : SH2000_PD_ARC,
				line, col, "%s", m);
	return 0;
}

int prog_arc_centre_r(struct prog_ctx *c, double s1, double s2, double e1,
		      double e2, double r, bool ccw, double *c1, double *c2,
		      unsigned int line, unsigned int col)
{
	double s[2] = { s1, s2 }, e[2] = { e1, e2 }, ctr[2];
	char m[200];

	if (sh2000_arc_centre_from_radius(s, e, r, ccw, ctr, m, sizeof(m)))
		return prog_err(c, SH2000_PD_ARC, line, col, "%s", m);
	*c1 = ctr[0];
	*c2 = ctr[1];
	return 0;
}

/* ---- NURBS ------------------------------------------------------------- */

int prog_nurbs_alloc(struct prog_ctx *c, struct prog_nurbs_buf *n,
		     unsigned int deg, size_t np)
{
	memset(n, 0, sizeof(*n));
	n->degree = deg;
	n->npoints = np;
	n->points = calloc(np, sizeof(*n->points));
	n->weights = calloc(np, sizeof(*n->weights));
	n->knots = calloc(np + deg + 1, sizeof(*n->knots));
	if (n->points && n->weights && n->knots)
		return 0;
	prog_nurbs_free(n);
	c->oom = c->stop = true;
	return -ENOMEM;
}

void prog_nurbs_free(struct prog_nurbs_buf *n)
{
	free(n->points);
	free(n->weights);
	free(n->knots);
	memset(n, 0, sizeof(*n));
}

struct sh2000_nurbs prog_nurbs_view(const struct prog_nurbs_buf *n)
{
	struct sh2000_nurbs v = {
		.degree = n->degree,
		.npoints = n->npoints,
		.points = (const double (*)[SH2000_AXES])n->points,
		.weights = n->weights,
		.knots = n->knots,
	};

	return v;
}

void prog_nurbs_give(struct prog_nurbs_buf *n, struct sh2000_prog_block *b)
{
	b->u.nurbs = prog_nurbs_view(n);
	memset(n, 0, sizeof(*n));
}

int prog_nurbs_check(struct prog_ctx *c, const struct sh2000_nurbs *n,
		     unsigned int line, unsigned int col)
{
	char m[200];
	int r = sh2000_nurbs_check(n, m, sizeof(m));

	if (!r)
		return 0;
	return prog_err(c, r == -ERANGE ? SH2000_PD_RANGE : SH2000_PD_NURBS,
			line, col, "%s", m);
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
	case SH2000_PROG_ARC:
		sh2000_arc_point(&b->u.arc, b->start, b->end, s, out);
		return 0;
	case SH2000_PROG_NURBS: {
		const struct sh2000_nurbs *n = &b->u.nurbs;
		double u0 = sh2000_nurbs_umin(n), u1 = sh2000_nurbs_umax(n);

		sh2000_nurbs_eval(n, u0 + s * (u1 - u0), out, NULL, NULL);
		return 0;
	}
	default:
		return -EINVAL;
	}
}
