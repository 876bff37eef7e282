// SPDX-License-Identifier: MIT
/*
 * Tool tables in LinuxCNC's format (program.h): "T1 P1 Z+10.0 D6.0 ;text",
 * one tool a line, the words LinuxCNC's tooldata reader knows. LinuxCNC
 * skips a line it cannot read with a note on its console; here every such
 * line is an error with its line and column, since a tool left out would
 * run a program with no offset, or stop it at its T word.
 */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prog_internal.h"

/* Tables are a few hundred lines; more than this is not a table. */
#define TABLE_MAX_BYTES (16u << 20)

/* A line's words: the letter's value, or not given. */
struct tword {
	bool has;
	double v;
	unsigned int col;
};

void sh2000_tool_table_init(struct sh2000_tool_table *t)
{
	memset(t, 0, sizeof(*t));
}

void sh2000_tool_table_free(struct sh2000_tool_table *t)
{
	for (size_t i = 0; i < t->count; i++)
		free(t->tools[i].comment);
	free(t->tools);
	free(t->file);
	memset(t, 0, sizeof(*t));
}

const struct sh2000_tool *
sh2000_tool_table_find(const struct sh2000_tool_table *t, int n)
{
	for (size_t i = 0; t && i < t->count; i++)
		if (t->tools[i].number == n)
			return &t->tools[i];
	return NULL;
}

static bool blank(char ch)
{
	return ch == ' ' || ch == '\t' || ch == '\f' || ch == '\v';
}

/* One word at s[0..n): its letter's slot in w[26]. */
static int read_word(struct prog_ctx *c, const char *s, size_t n,
		     unsigned int line, unsigned int col, struct tword *w)
{
	static const char known[] = "TPXYZABCUVWDIJQ";
	char L = (char)toupper((unsigned char)s[0]), buf[64], *end;
	struct tword *slot;

	if (!isalpha((unsigned char)s[0]) || !strchr(known, L))
		return prog_err(c, SH2000_PD_UNKNOWN, line, col,
				"'%.*s': not a tool table word (T P X Y Z A B C U V W D I J Q)",
				(int)(n > 20 ? 20 : n), s);
	slot = &w[L - 'A'];
	if (slot->has)
		return prog_err(c, SH2000_PD_CONFLICT, line, col,
				"%c given twice on one line", L);
	if (n < 2 || n - 1 >= sizeof(buf))
		return prog_err(c, SH2000_PD_SYNTAX, line, col,
				"%c without a number (the number follows the letter, as in T1 or Z+10.5)",
				L);
	memcpy(buf, s + 1, n - 1);
	buf[n - 1] = 0;
	slot->v = strtod(buf, &end);
	if (*end || !isfinite(slot->v))
		return prog_err(c, SH2000_PD_SYNTAX, line, col,
				"%c: '%s' is not a finite number", L, buf);
	/* a position plus an offset must stay a number */
	if (fabs(slot->v) > 1e9)
		return prog_err(c, SH2000_PD_RANGE, line, col,
				"%c%s: out of range (at most 1e9)", L, buf);
	if (strchr("TPQ", L) && (slot->v != floor(slot->v) ||
				 fabs(slot->v) > INT_MAX))
		return prog_err(c, SH2000_PD_RANGE, line, col,
				"%c%s: an integer is needed", L, buf);
	slot->has = true;
	slot->col = col;
	return 0;
}

/* The words a tool needs, and the axes this card has. */
static int check_words(struct prog_ctx *c, const struct tword *w,
		       const struct sh2000_tool_table *t, unsigned int line)
{
	const struct tword *T = &w['T' - 'A'], *P = &w['P' - 'A'];
	const struct sh2000_tool *same;

	if (!T->has)
		return prog_err(c, SH2000_PD_MISSING, line, 1,
				"no T word (tool number)");
	if (T->v < 1)
		return prog_err(c, SH2000_PD_RANGE, line, T->col,
				"T%g: tool numbers start at 1 (T0 is the empty spindle)",
				T->v);
	if (!P->has)
		return prog_err(c, SH2000_PD_MISSING, line, T->col,
				"T%d has no P word (pocket): LinuxCNC puts such a tool in the spindle's slot, where T%d and M6 do not find it",
				(int)T->v, (int)T->v);
	if (P->v < 0)
		return prog_err(c, SH2000_PD_RANGE, line, P->col,
				"P%g: a pocket number is not negative", P->v);
	for (const char *a = "BCUVW"; *a; a++)
		if (w[*a - 'A'].has && w[*a - 'A'].v != 0)
			return prog_err(c, SH2000_PD_NO_AXIS, line,
					w[*a - 'A'].col,
					"T%d has a %c offset: the SH-2000TH has no %c axis (its axes are X, Y, Z and the linear A)",
					(int)T->v, *a, *a);
	same = sh2000_tool_table_find(t, (int)T->v);
	if (same)
		return prog_err(c, SH2000_PD_CONFLICT, line, T->col,
				"T%d again: it is at line %u already", (int)T->v,
				same->line);
	return 0;
}

/* The comment after ';' with its blanks trimmed into *out (NULL: empty);
 * -ENOMEM. */
static int comment_of(const char *s, size_t n, char **out)
{
	*out = NULL;
	while (n && blank(*s))
		s++, n--;
	while (n && blank(s[n - 1]))
		n--;
	if (!n)
		return 0;
	*out = malloc(n + 1);
	if (!*out)
		return -ENOMEM;
	memcpy(*out, s, n);
	(*out)[n] = 0;
	return 0;
}

static int add_tool(struct prog_ctx *c, struct sh2000_tool_table *t,
		    const struct tword *w, const char *comment, size_t ncom,
		    unsigned int line)
{
	static const char axes[] = SH2000_AXIS_LETTERS;
	struct sh2000_tool *tool;

	if (t->count == t->cap) {
		size_t cap = t->cap ? t->cap * 2 : 16;
		void *p = realloc(t->tools, cap * sizeof(*t->tools));

		if (!p)
			goto oom;
		t->tools = p;
		t->cap = cap;
	}
	tool = &t->tools[t->count];
	memset(tool, 0, sizeof(*tool));
	tool->number = (int)w['T' - 'A'].v;
	tool->pocket = (int)w['P' - 'A'].v;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		tool->offset[a] = w[axes[a] - 'A'].v;
	tool->diameter = w['D' - 'A'].v;
	tool->front_angle = w['I' - 'A'].v;
	tool->back_angle = w['J' - 'A'].v;
	tool->orientation = (int)w['Q' - 'A'].v;
	tool->line = line;
	if (comment && comment_of(comment, ncom, &tool->comment))
		goto oom;
	t->count++;
	return 0;
oom:
	c->oom = c->stop = true;
	return -ENOMEM;
}

/* One line of the table (without its end). */
static int table_line(struct prog_ctx *c, struct sh2000_tool_table *t,
		      const char *s, size_t n, unsigned int line)
{
	const char *semi = memchr(s, ';', n);
	size_t words = semi ? (size_t)(semi - s) : n, i = 0;
	struct tword w[26];
	bool any = false;
	int ret;

	memset(w, 0, sizeof(w));
	while (i < words) {
		size_t k = i;

		if (blank(s[i])) {
			i++;
			continue;
		}
		while (k < words && !blank(s[k]))
			k++;
		ret = read_word(c, s + i, k - i, line, (unsigned)i + 1, w);
		if (ret)
			return ret;
		any = true;
		i = k;
	}
	if (!any)
		return 0;	/* blank, or a comment line */
	if ((ret = check_words(c, w, t, line)))
		return ret;
	return add_tool(c, t, w, semi ? semi + 1 : NULL,
			semi ? n - words - 1 : 0, line);
}

int sh2000_tool_table_read(struct sh2000_tool_table *t, const char *name,
			   const char *text, size_t len,
			   struct sh2000_prog_diags *diags)
{
	struct prog_ctx c;
	size_t off = 0;
	unsigned int line = 0;

	sh2000_tool_table_free(t);
	memset(&c, 0, sizeof(c));
	c.diags = diags;
	c.name = name ? name : "<tool table>";
	c.opt.max_errors = 20;
	t->file = strdup(c.name);
	if (!t->file)
		return -ENOMEM;
	while (off < len && !c.stop) {
		const char *s = text + off;
		const char *nl = memchr(s, '\n', len - off);
		size_t n = nl ? (size_t)(nl - s) : len - off;

		off += n + (nl != NULL);
		if (n && s[n - 1] == '\r')
			n--;
		table_line(&c, t, s, n, ++line);
	}
	if (c.oom || c.errors) {
		sh2000_tool_table_free(t);
		return c.oom ? -ENOMEM : -SH2000_PROG_EINVALID;
	}
	return 0;
}

int sh2000_tool_table_read_file(struct sh2000_tool_table *t, const char *path,
				struct sh2000_prog_diags *diags)
{
	struct prog_ctx c;
	FILE *f = fopen(path, "rb");
	char *buf = NULL;
	size_t len = 0, cap = 0, k;
	int ret = 0;

	sh2000_tool_table_free(t);
	while (f && !ret) {
		if (len == cap) {
			void *p = cap < TABLE_MAX_BYTES ?
				  realloc(buf, cap ? cap * 2 : 4096) : NULL;

			if (!p) {
				ret = cap < TABLE_MAX_BYTES ? -ENOMEM : -EFBIG;
				break;
			}
			buf = p;
			cap = cap ? cap * 2 : 4096;
		}
		k = fread(buf + len, 1, cap - len, f);
		len += k;
		if (k == 0)
			ret = ferror(f) ? -EIO : 1;
	}
	if (!f || ret < 0) {
		ret = f ? ret : -errno;
		memset(&c, 0, sizeof(c));
		c.diags = diags;
		c.name = path;
		c.opt.max_errors = 20;
		prog_err(&c, SH2000_PD_SYNTAX, 0, 0, "cannot read the tool table: %s",
			 strerror(-ret));
	} else {
		ret = sh2000_tool_table_read(t, path, buf, len, diags);
	}
	if (f)
		fclose(f);
	free(buf);
	return ret;
}
