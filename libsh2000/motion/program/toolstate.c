// SPDX-License-Identifier: MIT
/*
 * The tools of a program being read, for the G-code and the canonical
 * readers alike: T words checked against the tool table, tool changes
 * (a pause for the operator when asked, else reported once: the card has
 * no tool changer) and the offsets G43 and G43.2 take from the table.
 */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <string.h>

#include "prog_internal.h"

static const char *table_name(const struct prog_ctx *c)
{
	return c->opt.tools && c->opt.tools->file ? c->opt.tools->file :
	       "(unnamed)";
}

int prog_tool_select(struct prog_ctx *c, struct prog_tool_state *t,
		     double n, unsigned int line, unsigned int col)
{
	if (n != floor(n) || n < 0 || n > INT_MAX)
		return prog_err(c, SH2000_PD_RANGE, line, col,
				"T%g: a tool number is an integer >= 0", n);
	if (n > 0 && c->opt.tools &&
	    !sh2000_tool_table_find(c->opt.tools, (int)n))
		return prog_err(c, SH2000_PD_TOOL, line, col,
				"T%d: tool %d is not in the tool table %s",
				(int)n, (int)n, table_name(c));
	t->selected = (int)n;
	prog_warn_once(c, PW_TOOL, SH2000_PD_NOT_ACTED, line, col,
		       "T%d (tool select) not acted on by the card: the SH-2000TH has no tool changer, the tool is put in by hand; later T words are not reported",
		       (int)n);
	return 0;
}

int prog_tool_change(struct prog_ctx *c, struct prog_tool_state *t,
		     const char *what, unsigned int line, unsigned int col)
{
	struct sh2000_prog_block *b;

	t->loaded = t->selected;
	if (!c->opt.pause_at_tool_change)
		return prog_warn_once(c, PW_TOOLCHANGE, SH2000_PD_NOT_ACTED, line,
				      col,
				      "%s (tool change) not paused at: the SH-2000TH has no tool changer, and the program runs on as if T%d were in the spindle (a pause for the operator at each tool change is an option: sh2000-upload --pause-on-tool-change); later tool changes are not reported",
				      what, t->loaded);
	b = prog_push(c, SH2000_PROG_PAUSE, line, col);
	if (!b)
		return -ENOMEM;
	b->tool_change = true;
	b->tool = t->loaded;
	return 0;
}

int prog_tool_offsets(struct prog_ctx *c, int n, double out[SH2000_AXES],
		      const char *what, unsigned int line, unsigned int col)
{
	const struct sh2000_tool *tool;

	memset(out, 0, SH2000_AXES * sizeof(*out));
	if (n == 0)
		return 0;	/* the empty spindle: no offset */
	if (!c->opt.tools)
		return prog_err(c, SH2000_PD_TOOL, line, col,
				"%s: tool %d is not in the tool table: no tool table was given (sh2000-upload --tool-table FILE)",
				what, n);
	tool = sh2000_tool_table_find(c->opt.tools, n);
	if (!tool)
		return prog_err(c, SH2000_PD_TOOL, line, col,
				"%s: tool %d is not in the tool table %s", what,
				n, table_name(c));
	memcpy(out, tool->offset, SH2000_AXES * sizeof(*out));
	return 0;
}
