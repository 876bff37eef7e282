/* SPDX-License-Identifier: MIT */
/*
 * JSON NURBS files (docs/programs.md): one curve, or {"curves": [...]},
 * each with degree, knots, optional weights and control points, parsed
 * with json-c. Messages name the field and index; positions come from a
 * small scanner that finds that field in the text, since json-c keeps none.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <json-c/json.h>

#include "prog_internal.h"

/* ---- positions ---------------------------------------------------------- */

struct jstep {
	const char *key;	/* member name, or NULL for an index */
	long index;
};

static size_t jws(const char *t, size_t len, size_t i)
{
	while (i < len && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' ||
			   t[i] == '\r'))
		i++;
	return i;
}

/* Past one value starting at i (after white space). */
static size_t jskip(const char *t, size_t len, size_t i)
{
	int depth = 0;

	i = jws(t, len, i);
	do {
		if (i >= len)
			return len;
		if (t[i] == '"') {
			for (i++; i < len && t[i] != '"'; i++)
				if (t[i] == '\\')
					i++;
			i++;
		} else if (t[i] == '{' || t[i] == '[') {
			depth++;
			i++;
		} else if (t[i] == '}' || t[i] == ']') {
			depth--;
			i++;
		} else if (depth == 0) {
			while (i < len && !strchr(",]} \t\r\n", t[i]))
				i++;
		} else {
			i++;
		}
	} while (depth > 0);
	return i;
}

/* Offset of the value at path from the value at i, or (size_t)-1. */
static size_t jlocate(const char *t, size_t len, size_t i,
		      const struct jstep *path, int n)
{
	i = jws(t, len, i);
	if (n == 0)
		return i;
	if (i >= len)
		return (size_t)-1;
	if (t[i] == '{' && path->key) {
		size_t klen = strlen(path->key), found = (size_t)-1;

		i = jws(t, len, i + 1);
		while (i < len && t[i] == '"') {
			size_t ks = i + 1, ke = ks;

			while (ke < len && t[ke] != '"')
				ke += t[ke] == '\\' ? 2 : 1;
			i = jws(t, len, ke + 1);
			if (i >= len || t[i] != ':')
				break;
			/* the last one wins, as in json-c */
			if (ke - ks == klen && !memcmp(t + ks, path->key, klen))
				found = jlocate(t, len, i + 1, path + 1, n - 1);
			i = jws(t, len, jskip(t, len, i + 1));
			if (i < len && t[i] == ',')
				i = jws(t, len, i + 1);
		}
		return found;
	}
	if (t[i] == '[' && !path->key) {
		long k = 0;

		i = jws(t, len, i + 1);
		while (i < len && t[i] != ']') {
			if (k == path->index)
				return jlocate(t, len, i, path + 1, n - 1);
			i = jws(t, len, jskip(t, len, i));
			if (i < len && t[i] == ',')
				i = jws(t, len, i + 1);
			k++;
		}
	}
	return (size_t)-1;
}

static void jlinecol(const char *t, size_t off, unsigned int *line,
		     unsigned int *col)
{
	*line = 1;
	*col = 1;
	for (size_t i = 0; i < off; i++) {
		if (t[i] == '\n') {
			(*line)++;
			*col = 1;
		} else {
			(*col)++;
		}
	}
}

struct jctx {
	struct prog_ctx *c;
	const char *text;
	size_t len;
	long curve;		/* index in "curves", or -1 */
	double last_feed;	/* of the last FEED block, mm/s */
	char prefix[32];	/* "curves[2]." or "" */
};

/* An error at field key[i1][i2] of the current curve (key NULL: the curve;
 * i1, i2 < 0: none). */
static int jerr(struct jctx *j, enum sh2000_prog_diag_code code,
		const char *key, long i1, long i2, const char *fmt, ...)
	__attribute__((format(printf, 6, 7)));

static int jerr(struct jctx *j, enum sh2000_prog_diag_code code,
		const char *key, long i1, long i2, const char *fmt, ...)
{
	struct jstep path[5];
	int n = 0;
	size_t off;
	unsigned int line = 1, col = 1;
	char msg[512], where[96];
	va_list ap;

	if (j->curve >= 0) {
		path[n++] = (struct jstep){ "curves", 0 };
		path[n++] = (struct jstep){ NULL, j->curve };
	}
	if (key) {
		path[n++] = (struct jstep){ key, 0 };
		if (i1 >= 0)
			path[n++] = (struct jstep){ NULL, i1 };
		if (i2 >= 0)
			path[n++] = (struct jstep){ NULL, i2 };
	}
	/* a missing field points at its object */
	while (n >= 0) {
		off = jlocate(j->text, j->len, 0, path, n);
		if (off != (size_t)-1) {
			jlinecol(j->text, off, &line, &col);
			break;
		}
		n--;
	}
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (!key)
		if (j->curve >= 0)
			snprintf(where, sizeof(where), "curves[%ld]: ", j->curve);
		else
			where[0] = 0;
	else if (i2 >= 0)
		snprintf(where, sizeof(where), "%s%s[%ld][%ld]: ", j->prefix, key, i1, i2);
	else if (i1 >= 0)
		snprintf(where, sizeof(where), "%s%s[%ld]: ", j->prefix, key, i1);
	else
		snprintf(where, sizeof(where), "%s%s: ", j->prefix, key);
	return prog_err(j->c, code, line, col, "%s%s", where, msg);
}

/* ---- curves ---------------------------------------------------------------- */

static bool jnumber(struct json_object *o, double *v)
{
	if (!o || (!json_object_is_type(o, json_type_double) &&
		   !json_object_is_type(o, json_type_int)))
		return false;
	*v = json_object_get_double(o);
	return true;
}

static const char *jtype(struct json_object *o)
{
	return o ? json_type_to_name(json_object_get_type(o)) : "null";
}

/* The fields of a curve object are known ones; its feed (or the file's,
 * or the options'). */
static int curve_feed(struct jctx *j, struct json_object *cv, double *feed)
{
	struct json_object *o;

	if (!json_object_is_type(cv, json_type_object))
		return jerr(j, SH2000_PD_SYNTAX, NULL, -1, -1,
			    "a curve is an object, found %s", jtype(cv));
	json_object_object_foreach(cv, key, val) {
		(void)val;
		if (strcmp(key, "degree") && strcmp(key, "knots") &&
		    strcmp(key, "weights") && strcmp(key, "points") &&
		    strcmp(key, "feed") && strcmp(key, "comment") &&
		    (j->curve >= 0 || (strcmp(key, "format"))))
			return jerr(j, SH2000_PD_UNKNOWN, key, -1, -1,
				    "unknown field (fields: degree, knots, weights, points, feed, comment)");
	}
	if (json_object_object_get_ex(cv, "feed", &o)) {
		if (!jnumber(o, feed) || !isfinite(*feed) || !(*feed > 0))
			return jerr(j, SH2000_PD_RANGE, "feed", -1, -1,
				    "must be a number > 0 (mm/s)");
	}
	if (!(*feed > 0))
		*feed = j->c->opt.feed_mm_s;
	if (!(*feed > 0))
		return jerr(j, SH2000_PD_FEED, NULL, -1, -1,
			    "no feed: give \"feed\" in mm/s");
	return 0;
}

/* The arrays of a curve and their sizes. */
struct jcurve {
	struct json_object *points, *knots, *weights;
	unsigned int degree;
	size_t np, nk;
};

static int curve_degree_points(struct jctx *j, struct json_object *cv,
			       struct jcurve *k)
{
	struct json_object *deg;

	if (!json_object_object_get_ex(cv, "degree", &deg))
		return jerr(j, SH2000_PD_MISSING, NULL, -1, -1,
			    "\"degree\" missing");
	if (!json_object_is_type(deg, json_type_int) ||
	    json_object_get_int64(deg) < 1 ||
	    json_object_get_int64(deg) > SH2000_NURBS_MAX_DEGREE)
		return jerr(j, SH2000_PD_RANGE, "degree", -1, -1,
			    "must be an integer from 1 to %d", SH2000_NURBS_MAX_DEGREE);
	k->degree = (unsigned int)json_object_get_int64(deg);
	if (!json_object_object_get_ex(cv, "points", &k->points))
		return jerr(j, SH2000_PD_MISSING, NULL, -1, -1,
			    "\"points\" missing");
	if (!json_object_is_type(k->points, json_type_array))
		return jerr(j, SH2000_PD_SYNTAX, "points", -1, -1,
			    "must be an array of [x, y(, z(, a))] points, found %s",
			    jtype(k->points));
	k->np = json_object_array_length(k->points);
	if (k->np < (size_t)k->degree + 1)
		return jerr(j, SH2000_PD_NURBS, "points", -1, -1,
			    "%zu control points, a degree %u curve needs at least %u",
			    k->np, k->degree, k->degree + 1);
	return 0;
}

static int curve_shape(struct jctx *j, struct json_object *cv,
		       struct jcurve *k)
{
	int ret = curve_degree_points(j, cv, k);

	if (ret)
		return ret;
	if (!json_object_object_get_ex(cv, "knots", &k->knots))
		return jerr(j, SH2000_PD_MISSING, NULL, -1, -1,
			    "\"knots\" missing (points + degree + 1 = %zu values)",
			    k->np + k->degree + 1);
	if (!json_object_is_type(k->knots, json_type_array))
		return jerr(j, SH2000_PD_SYNTAX, "knots", -1, -1,
			    "must be an array of numbers, found %s", jtype(k->knots));
	k->nk = json_object_array_length(k->knots);
	if (k->nk != k->np + k->degree + 1)
		return jerr(j, SH2000_PD_NURBS, "knots", -1, -1,
			    "%zu knots, expected points + degree + 1 = %zu + %u + 1 = %zu",
			    k->nk, k->np, k->degree, k->np + k->degree + 1);
	k->weights = NULL;
	if (json_object_object_get_ex(cv, "weights", &k->weights)) {
		if (!json_object_is_type(k->weights, json_type_array))
			return jerr(j, SH2000_PD_SYNTAX, "weights", -1, -1,
				    "must be an array of numbers, found %s",
				    jtype(k->weights));
		if (json_object_array_length(k->weights) != k->np)
			return jerr(j, SH2000_PD_NURBS, "weights", -1, -1,
				    "%zu weights for %zu control points",
				    json_object_array_length(k->weights), k->np);
	}
	return 0;
}

static int fill_knots(struct jctx *j, const struct jcurve *k,
		      struct prog_nurbs_buf *n)
{
	for (size_t i = 0; i < k->nk; i++) {
		struct json_object *o = json_object_array_get_idx(k->knots, i);

		if (!jnumber(o, &n->knots[i]) || !isfinite(n->knots[i]))
			return jerr(j, SH2000_PD_SYNTAX, "knots", (long)i, -1,
				    "must be a finite number, found %s", jtype(o));
		if (i && n->knots[i] < n->knots[i - 1])
			return jerr(j, SH2000_PD_NURBS, "knots", (long)i, -1,
				    "%g is less than knots[%zu] = %g: knots must not decrease",
				    n->knots[i], i - 1, n->knots[i - 1]);
	}
	return 0;
}

/* Control point i (missing axes stay where the machine is) and weight. */
static int fill_point(struct jctx *j, const struct jcurve *k,
		      struct prog_nurbs_buf *n, size_t i)
{
	struct json_object *pt = json_object_array_get_idx(k->points, i), *o;
	size_t dim;

	n->weights[i] = 1;
	if (k->weights) {
		o = json_object_array_get_idx(k->weights, i);
		if (!jnumber(o, &n->weights[i]) || !isfinite(n->weights[i]) ||
		    !(n->weights[i] > 0))
			return jerr(j, SH2000_PD_NURBS, "weights", (long)i, -1,
				    "must be a number > 0");
	}
	if (!json_object_is_type(pt, json_type_array) ||
	    (dim = json_object_array_length(pt)) < 2 || dim > 4)
		return jerr(j, SH2000_PD_SYNTAX, "points", (long)i, -1,
			    "a point is [x, y], [x, y, z] or [x, y, z, a] in mm");
	memcpy(n->points[i], j->c->pos, sizeof(n->points[i]));
	for (size_t a = 0; a < dim; a++) {
		o = json_object_array_get_idx(pt, a);
		if (!jnumber(o, &n->points[i][a]) || !isfinite(n->points[i][a]))
			return jerr(j, SH2000_PD_SYNTAX, "points", (long)i, (long)a,
				    "must be a finite number, found %s", jtype(o));
	}
	return 0;
}

/* Line and column of the current curve (or of field key in it). */
static void curve_pos(struct jctx *j, const char *key, unsigned int *line,
		      unsigned int *col)
{
	struct jstep path[3] = { { "curves", 0 }, { NULL, j->curve },
				 { key, 0 } };
	int n = key ? 3 : 2;
	size_t off = j->curve >= 0 ? jlocate(j->text, j->len, 0, path, n) :
			 jlocate(j->text, j->len, 0, path + 2, key ? 1 : 0);

	*line = 1;
	*col = 1;
	if (off != (size_t)-1)
		jlinecol(j->text, off, line, col);
}

/* The blocks of a checked curve: a rapid to its start if the machine is
 * elsewhere, a feed change, the curve. */
static int curve_blocks(struct jctx *j, struct prog_nurbs_buf *n, double feed)
{
	struct prog_ctx *c = j->c;
	struct sh2000_nurbs v = prog_nurbs_view(n);
	struct sh2000_prog_block *b;
	double start[SH2000_AXES];
	unsigned int line, col;

	curve_pos(j, NULL, &line, &col);
	sh2000_nurbs_eval(&v, sh2000_nurbs_umin(&v), start, NULL, NULL);
	if (memcmp(start, c->pos, sizeof(start))) {
		b = prog_push(c, SH2000_PROG_RAPID, line, col);
		if (!b)
			return -ENOMEM;
		memcpy(b->end, start, sizeof(start));
		memcpy(c->pos, start, sizeof(start));
	}
	if (feed != j->last_feed) {
		b = prog_push(c, SH2000_PROG_FEED, line, col);
		if (!b)
			return -ENOMEM;
		b->feed = feed;
		b->u.feed_mm_min = feed * 60;
		j->last_feed = feed;
	}
	b = prog_push(c, SH2000_PROG_NURBS, line, col);
	if (!b)
		return -ENOMEM;
	b->feed = feed;
	sh2000_nurbs_eval(&v, sh2000_nurbs_umax(&v), b->end, NULL, NULL);
	memcpy(c->pos, b->end, sizeof(c->pos));
	prog_nurbs_give(n, b);
	return 0;
}

static int read_curve(struct jctx *j, struct json_object *cv, double feed)
{
	struct prog_nurbs_buf n;
	struct sh2000_nurbs v;
	struct jcurve k;
	unsigned int line, col;
	int ret;

	ret = curve_feed(j, cv, &feed);
	if (!ret)
		ret = curve_shape(j, cv, &k);
	if (!ret)
		ret = prog_nurbs_alloc(j->c, &n, k.degree, k.np);
	if (ret)
		return ret;
	ret = fill_knots(j, &k, &n);
	for (size_t i = 0; !ret && i < k.np; i++)
		ret = fill_point(j, &k, &n, i);
	if (!ret) {
		/* the rest (interior knot multiplicity, empty domain) */
		curve_pos(j, "knots", &line, &col);
		v = prog_nurbs_view(&n);
		ret = prog_nurbs_check(j->c, &v, line, col);
	}
	if (!ret)
		ret = curve_blocks(j, &n, feed);
	prog_nurbs_free(&n);
	return ret;
}

static int read_document(struct prog_ctx *c, const char *text, size_t len)
{
	struct json_tokener *tok = json_tokener_new();
	struct json_object *root, *curves, *o;
	struct jctx j = { .c = c, .text = text, .len = len, .curve = -1 };
	enum json_tokener_error jerrc;
	double feed = 0;
	unsigned int line, col;
	size_t end;

	if (!tok) {
		c->oom = c->stop = true;
		return -ENOMEM;
	}
	json_tokener_set_flags(tok, JSON_TOKENER_STRICT);
	root = json_tokener_parse_ex(tok, text, (int)(len > (size_t)0x7fffffff ?
						     0x7fffffff : len));
	jerrc = json_tokener_get_error(tok);
	end = json_tokener_get_parse_end(tok);
	json_tokener_free(tok);
	if (!root || jerrc != json_tokener_success) {
		/* json-c stops at the offending character */
		jlinecol(text, jerrc == json_tokener_continue ? len : end, &line, &col);
		json_object_put(root);
		return prog_err(c, SH2000_PD_SYNTAX, line, col, "JSON: %s",
				jerrc == json_tokener_continue ?
				"unexpected end of file" :
				json_tokener_error_desc(jerrc));
	}
	if (jws(text, len, end) < len) {
		jlinecol(text, jws(text, len, end), &line, &col);
		json_object_put(root);
		return prog_err(c, SH2000_PD_SYNTAX, line, col,
				"JSON: text after the end of the document");
	}
	if (!json_object_is_type(root, json_type_object)) {
		json_object_put(root);
		return prog_err(c, SH2000_PD_SYNTAX, 1, 1,
				"a NURBS file is a JSON object, found %s",
				jtype(root));
	}
	if (json_object_object_get_ex(root, "format", &o) &&
	    (!json_object_is_type(o, json_type_string) ||
	     strcmp(json_object_get_string(o), "sh2000-nurbs-1"))) {
		jerr(&j, SH2000_PD_UNSUPPORTED, "format", -1, -1,
		     "only \"sh2000-nurbs-1\" is known");
		goto out;
	}
	if (json_object_object_get_ex(root, "curves", &curves)) {
		size_t n;

		json_object_object_foreach(root, key, val) {
			(void)val;
			if (strcmp(key, "curves") && strcmp(key, "feed") &&
			    strcmp(key, "format") && strcmp(key, "comment")) {
				jerr(&j, SH2000_PD_UNKNOWN, key, -1, -1,
				     "unknown top-level field next to \"curves\" (fields: format, feed, curves, comment)");
				goto out;
			}
		}
		if (json_object_object_get_ex(root, "feed", &o) &&
		    (!jnumber(o, &feed) || !isfinite(feed) || !(feed > 0))) {
			jerr(&j, SH2000_PD_RANGE, "feed", -1, -1,
			     "must be a number > 0 (mm/s)");
			goto out;
		}
		if (!json_object_is_type(curves, json_type_array) ||
		    (n = json_object_array_length(curves)) == 0) {
			jerr(&j, SH2000_PD_SYNTAX, "curves", -1, -1,
			     "must be a non-empty array of curves");
			goto out;
		}
		for (size_t i = 0; i < n && !c->stop; i++) {
			j.curve = (long)i;
			snprintf(j.prefix, sizeof(j.prefix), "curves[%zu].", i);
			if (read_curve(&j, json_object_array_get_idx(curves, i),
				       feed) == -ENOMEM)
				break;
		}
	} else {
		read_curve(&j, root, 0);
	}
out:
	json_object_put(root);
	return c->errors ? -SH2000_PROG_EINVALID : 0;
}

/* JSON is not read line by line: the lines are gathered and the document
 * parsed at the end (a NURBS file holds curves, not millions of moves). */
struct json_state {
	char *text;
	size_t len, cap;
};

static void json_init(struct prog_ctx *c, void *state)
{
	(void)c;
	memset(state, 0, sizeof(struct json_state));
}

static void json_line(struct prog_ctx *c, void *state, const char *s,
		      size_t n, unsigned int line)
{
	struct json_state *st = state;

	(void)line;
	/* lines joined by their ends: positions as in the file */
	if (st->len + n + 1 > st->cap) {
		size_t cap = (st->len + n + 1) * 2;
		char *t = realloc(st->text, cap);

		if (!t) {
			c->oom = c->stop = true;
			return;
		}
		st->text = t;
		st->cap = cap;
	}
	if (line > 1)
		st->text[st->len++] = '\n';
	memcpy(st->text + st->len, s, n);
	st->len += n;
}

static void json_finish(struct prog_ctx *c, void *state, unsigned int line)
{
	struct json_state *st = state;

	(void)line;
	if (!c->stop)
		read_document(c, st->text ? st->text : "", st->len);
}

static void json_release(void *state)
{
	struct json_state *st = state;

	free(st->text);
	memset(st, 0, sizeof(*st));
}

const struct prog_format_ops prog_json_ops = {
	.state_size = sizeof(struct json_state),
	.init = json_init,
	.line = json_line,
	.finish = json_finish,
	.release = json_release,
};
