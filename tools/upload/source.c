// SPDX-License-Identifier: MIT
/*
 * The program sh2000-upload runs: a reader over the file, or over what
 * LinuxCNC's rs274 made of it (--rs274), with its diagnostics.
 */
#include <stdio.h>
#include <string.h>

#include "upload.h"

/* --tool-table: 0 or an exit code, the errors printed. */
static int read_tools(struct upl_source *s, const struct upl_opts *o)
{
	int r;

	if (!o->tool_table)
		return SH2000_EXIT_OK;
	r = sh2000_tool_table_read_file(&s->tools, o->tool_table, &s->diags);
	if (!r)
		return SH2000_EXIT_OK;
	sh2000_prog_diags_print(&s->diags, stderr);
	if (r == -SH2000_PROG_EINVALID) {
		sh2000_tool_msg("--tool-table %s: %zu error%s; nothing moved",
				o->tool_table, s->diags.errors,
				s->diags.errors == 1 ? "" : "s");
		return SH2000_EXIT_INPUT;
	}
	return SH2000_EXIT_CARD;	/* cannot be read */
}

int upl_source_open(struct upl_source *s, const struct upl_opts *o,
		    const double start[SH2000_AXES])
{
	struct sh2000_prog_options po;
	int r, x;

	memset(s, 0, sizeof(*s));
	sh2000_prog_diags_init(&s->diags);
	sh2000_tool_table_init(&s->tools);
	x = read_tools(s, o);
	if (x)
		return x;
	sh2000_prog_options_default(&po);
	memcpy(po.start, start, sizeof(po.start));
	po.feed_mm_s = o->feed_mm_min / 60.0;
	po.tools = o->tool_table ? &s->tools : NULL;
	po.pause_at_tool_change = o->pause_tool_change;
	if (o->rs274) {
		x = upl_rs274_run(o, s);
		if (x)
			return x;
		r = sh2000_prog_reader_open(&s->reader, SH2000_PROG_CANON,
					    s->canon, &po, &s->diags);
	} else {
		r = sh2000_prog_reader_open(&s->reader, o->format, o->file,
					    &po, &s->diags);
	}
	if (!r)
		return SH2000_EXIT_OK;
	sh2000_prog_diags_print(&s->diags, stderr);
	if (r == -SH2000_PROG_EFORMAT)
		return sh2000_tool_usage(NULL,
			"%s: cannot tell the format from the name; use --format",
			o->file);
	/* the file cannot be read: an I/O error, not the program's */
	if (!s->diags.count)
		sh2000_tool_msg("%s: %s", o->file, sh2000_strerror(r));
	return SH2000_EXIT_CARD;
}

int upl_source_errors(struct upl_source *s, const struct upl_opts *o)
{
	sh2000_prog_diags_print(&s->diags, stderr);
	sh2000_tool_msg("%s: %zu error%s; nothing moved", o->file,
			s->diags.errors, s->diags.errors == 1 ? "" : "s");
	if (o->rs274) {
		/* the positions point into rs274's output */
		sh2000_tool_msg("--rs274: rs274's output is kept in %s",
				s->canon);
		s->dir[0] = 0;
	}
	return SH2000_EXIT_INPUT;
}

void upl_source_close(struct upl_source *s)
{
	sh2000_prog_reader_close(s->reader);
	s->reader = NULL;
	upl_rs274_clean(s);
	sh2000_tool_table_free(&s->tools);
	sh2000_prog_diags_free(&s->diags);
}
