// SPDX-License-Identifier: MIT
/*
 * Reading a program block by block in constant memory (program.h): the
 * driver that feeds a format's line reader one line at a time from a file
 * (or text in memory) and hands out the blocks each line made. Only the
 * current line and its blocks are held, so a program of any length reads
 * in the same memory. Standard input is spooled to a temporary file so
 * that a reader can always be rewound for a second pass (check and plan
 * first, then stream).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prog_internal.h"

/* Longer lines are an error (the rest of the line is skipped): no program
 * line needs more, and a file without line ends must not fill memory. */
#define LINE_MAX_BYTES (1u << 20)

struct sh2000_prog_reader {
	struct prog_ctx c;
	struct sh2000_program queue;	/* the blocks of the current line */
	size_t next;			/* next block of the queue to hand out */
	const struct prog_format_ops *ops;
	void *state;
	char *name;
	/* the source: a file (owned) or text in memory */
	FILE *f;
	const char *text;
	size_t len, off;
	char *line;			/* line buffer for files */
	size_t line_cap;
	unsigned int lineno;
	bool finished;			/* the format's finish has run */
};

static const struct prog_format_ops *format_ops(enum sh2000_prog_format f)
{
	switch (f) {
	case SH2000_PROG_GCODE:
		return &prog_gcode_ops;
	case SH2000_PROG_CANON:
		return &prog_canon_ops;
	case SH2000_PROG_CSV:
		return &prog_csv_ops;
	case SH2000_PROG_NURBS_JSON:
		return &prog_json_ops;
	default:
		return NULL;
	}
}

/* Back to the first line with fresh state and the machine at the start. */
static void restart(struct sh2000_prog_reader *r)
{
	if (r->ops->release)
		r->ops->release(r->state);
	prog_clear_blocks(&r->queue);
	r->next = 0;
	memset(r->state, 0, r->ops->state_size);
	r->c.errors = 0;
	r->c.stop = false;
	r->c.warned = 0;
	memcpy(r->c.pos, r->c.opt.start, sizeof(r->c.pos));
	r->off = 0;
	r->lineno = 0;
	r->finished = false;
	r->ops->init(&r->c, r->state);
}

/* Set up everything but the source. */
static int reader_new(struct sh2000_prog_reader **out,
		      enum sh2000_prog_format fmt, const char *name,
		      const struct sh2000_prog_options *opt,
		      struct sh2000_prog_diags *diags)
{
	struct sh2000_prog_reader *r;

	*out = NULL;
	if (fmt == SH2000_PROG_AUTO)
		fmt = sh2000_prog_format_guess(name);
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->c.diags = diags;
	r->c.prog = &r->queue;
	if (opt)
		r->c.opt = *opt;
	else
		sh2000_prog_options_default(&r->c.opt);
	if (r->c.opt.max_errors == 0)
		r->c.opt.max_errors = 20;
	r->name = strdup(name);
	r->queue.file = strdup(name);
	r->ops = format_ops(fmt);
	r->state = r->ops ? calloc(1, r->ops->state_size) : NULL;
	r->c.name = r->name;
	*out = r;
	if (!r->name || !r->queue.file || (r->ops && !r->state))
		return -ENOMEM;
	if (!r->ops) {
		prog_err(&r->c, SH2000_PD_UNKNOWN, 0, 0,
			 "cannot tell the program format from the name (use .ngc, .nc, .gcode, .canon, .csv or .json, or name the format)");
		return -SH2000_PROG_EFORMAT;
	}
	for (unsigned int i = 0; i < SH2000_AXES; i++)
		if (!isfinite(r->c.opt.start[i]))
			prog_err(&r->c, SH2000_PD_RANGE, 0, 0,
				 "start position of axis %c is not finite",
				 SH2000_AXIS_LETTERS[i]);
	if (r->c.errors)
		return -SH2000_PROG_EINVALID;
	restart(r);
	return 0;
}

int sh2000_prog_reader_open_text(struct sh2000_prog_reader **out,
				 enum sh2000_prog_format fmt, const char *name,
				 const char *text, size_t len,
				 const struct sh2000_prog_options *opt,
				 struct sh2000_prog_diags *diags)
{
	int r = reader_new(out, fmt, name ? name : "<program>", opt, diags);

	if (*out) {
		(*out)->text = text ? text : "";
		(*out)->len = text ? len : 0;
	}
	if (r) {
		sh2000_prog_reader_close(*out);
		*out = NULL;
	}
	return r;
}

/* Standard input into a temporary file, so that it can be read twice. */
static int spool_stdin(FILE **out)
{
	char buf[65536];
	FILE *t = tmpfile();
	size_t n;

	if (!t)
		return -errno;
	while ((n = fread(buf, 1, sizeof(buf), stdin)) > 0)
		if (fwrite(buf, 1, n, t) != n) {
			fclose(t);
			return -EIO;
		}
	if (ferror(stdin) || fflush(t) || fseek(t, 0, SEEK_SET)) {
		fclose(t);
		return -EIO;
	}
	*out = t;
	return 0;
}

static int open_source(const char *path, FILE **f)
{
	if (!strcmp(path, "-"))
		return spool_stdin(f);
	*f = fopen(path, "rb");
	return *f ? 0 : -errno;
}

int sh2000_prog_reader_open(struct sh2000_prog_reader **out,
			    enum sh2000_prog_format fmt, const char *path,
			    const struct sh2000_prog_options *opt,
			    struct sh2000_prog_diags *diags)
{
	bool is_stdin = !strcmp(path, "-");
	const char *name = is_stdin ? "<stdin>" : path;
	FILE *f = NULL;
	int r;

	if (fmt == SH2000_PROG_AUTO && is_stdin)
		fmt = SH2000_PROG_GCODE;
	r = reader_new(out, fmt, name, opt, diags);
	if (!r) {
		r = open_source(path, &f);
		if (r)
			prog_err(&(*out)->c, SH2000_PD_SYNTAX, 0, 0,
				 "cannot read: %s", strerror(-r));
		(*out)->f = f;
	}
	if (r) {
		sh2000_prog_reader_close(*out);
		*out = NULL;
	}
	return r;
}

/* The next line of a file into r->line; 1, 0 at the end, or -errno. A
 * line longer than LINE_MAX_BYTES is cut there (*cut set). A reader
 * belongs to one thread: the stream's lock is not needed per byte. */
static int file_line(struct sh2000_prog_reader *r, size_t *n, bool *cut)
{
	size_t len = 0;
	int ch;

	*cut = false;
	while ((ch = getc_unlocked(r->f)) != EOF && ch != '\n') {
		if (len + 1 >= r->line_cap && len < LINE_MAX_BYTES) {
			size_t cap = r->line_cap ? r->line_cap * 2 : 256;
			char *l = realloc(r->line, cap);

			if (!l)
				return -ENOMEM;
			r->line = l;
			r->line_cap = cap;
		}
		if (len < LINE_MAX_BYTES)
			r->line[len++] = (char)ch;
		else
			*cut = true;
	}
	if (ferror(r->f))
		return -EIO;
	if (ch == EOF && len == 0)
		return 0;
	if (len && r->line[len - 1] == '\r')
		len--;
	*n = len;
	return 1;
}

/* The next line of text in memory. */
static int text_line(struct sh2000_prog_reader *r, const char **s, size_t *n)
{
	size_t e = r->off;

	if (r->off >= r->len)
		return 0;
	while (e < r->len && r->text[e] != '\n')
		e++;
	*s = r->text + r->off;
	*n = e - r->off;
	if (*n && (*s)[*n - 1] == '\r')
		(*n)--;
	r->off = e < r->len ? e + 1 : r->len;
	return 1;
}

/* Feed one line to the format (or finish it at the end): 1 when a line
 * was fed, 0 when the input is done, or -errno. */
static int step(struct sh2000_prog_reader *r)
{
	const char *s = NULL, *nul;
	size_t n = 0;
	bool cut = false;
	int got;

	if (r->finished)
		return 0;
	got = r->c.stop ? 0 : r->f ? file_line(r, &n, &cut) : text_line(r, &s, &n);
	if (got < 0)
		return got;
	if (got == 0) {
		r->ops->finish(&r->c, r->state, r->lineno);
		r->finished = true;
		return 0;
	}
	r->lineno++;
	if (r->f)
		s = r->line ? r->line : "";
	if (cut)
		prog_err(&r->c, SH2000_PD_SYNTAX, r->lineno, LINE_MAX_BYTES + 1,
			 "line longer than %u bytes", LINE_MAX_BYTES);
	/* every format is text: a NUL would end a number or a word early
	 * and the rest of it would be read as something else ("0.\0\0001"
	 * as a tolerance of 0, no tolerance at all), so the line is refused */
	nul = memchr(s, '\0', n);
	if (nul) {
		prog_err(&r->c, SH2000_PD_SYNTAX, r->lineno,
			 (unsigned int)(nul - s) + 1,
			 "a NUL byte: not a text program (line skipped)");
		return r->c.oom ? -ENOMEM : 1;
	}
	r->ops->line(&r->c, r->state, s, n, r->lineno);
	return r->c.oom ? -ENOMEM : 1;
}

int sh2000_prog_reader_next(struct sh2000_prog_reader *r,
			    const struct sh2000_prog_block **b)
{
	unsigned int errors = r->c.errors;
	int got;

	*b = NULL;
	while (r->next == r->queue.count) {
		prog_clear_blocks(&r->queue);
		r->next = 0;
		got = step(r);
		if (got < 0)
			return got;
		if (r->c.replay && r->c.errors > errors)
			return -SH2000_PROG_EINVALID;	/* changed since */
		if (got == 0 && r->next == r->queue.count)
			return 0;
	}
	*b = &r->queue.blocks[r->next++];
	return 1;
}

int sh2000_prog_reader_rewind(struct sh2000_prog_reader *r)
{
	if (r->f && fseek(r->f, 0, SEEK_SET))
		return -errno;
	restart(r);
	r->c.replay = true;
	return 0;
}

int sh2000_prog_reader_axes(struct sh2000_prog_reader *r,
			    const double at[SH2000_AXES], unsigned int *moves)
{
	const struct sh2000_prog_block *b;
	/* nothing read since it was opened: it stays so, and the next read
	 * gives every warning; else the scan is a rewind */
	bool fresh = !r->c.replay && r->lineno == 0 && !r->finished;
	int got, e;

	*moves = 0;
	e = sh2000_prog_reader_rewind(r);
	if (e)
		return e;
	/* a scan: no diagnostic, none counted against the next read */
	r->c.quiet = true;
	r->c.replay = false;
	/* what follows the program's end is never planned */
	while ((got = sh2000_prog_reader_next(r, &b)) > 0 &&
	       b->kind != SH2000_PROG_END)
		*moves |= sh2000_prog_block_axes(b, at);
	r->c.quiet = false;
	e = sh2000_prog_reader_rewind(r);
	r->c.replay = !fresh;
	return got < 0 ? got : e;
}

unsigned int sh2000_prog_reader_errors(const struct sh2000_prog_reader *r)
{
	return r->c.errors;
}

unsigned int sh2000_prog_reader_line(const struct sh2000_prog_reader *r)
{
	return r->lineno;
}

void sh2000_prog_reader_close(struct sh2000_prog_reader *r)
{
	if (!r)
		return;
	if (r->ops && r->state && r->ops->release)
		r->ops->release(r->state);
	if (r->f)
		fclose(r->f);
	sh2000_program_free(&r->queue);
	free(r->state);
	free(r->line);
	free(r->name);
	free(r);
}

/* The whole program: every block of a reader into prog. */
int prog_read_all(struct sh2000_prog_reader *r, struct sh2000_program *prog)
{
	int got;

	prog->file = r->queue.file;
	r->queue.file = NULL;
	r->c.prog = prog;
	while ((got = step(r)) > 0)
		;
	r->c.prog = &r->queue;
	r->queue.file = strdup(prog->file);
	if (got < 0 || r->c.oom)
		return got < 0 ? got : -ENOMEM;
	return r->c.errors ? -SH2000_PROG_EINVALID : 0;
}
