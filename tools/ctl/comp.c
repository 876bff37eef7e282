// SPDX-License-Identifier: MIT
/*
 * sh2000ctl comp: the card's compensation tables (protocol 1.5,
 * docs/compensation.md): load a table file, show what is active (and
 * whether a file is it), clear them. The rules are the library's: the
 * file is checked against the card's limits before anything is sent and
 * the card checks it again; a refusal names FILE:LINE and changes nothing.
 */
#include <string.h>

#include <sh2000/sh2000_protocol.h>

#include "ctl.h"

static const char *state_name(unsigned int s)
{
	switch (s) {
	case SH2000_COMP_NONE: return "none";
	case SH2000_COMP_ACTIVE: return "active";
	case SH2000_COMP_SWITCHING: return "switching";
	default: return "?";
	}
}

static int show(struct ctl *c, const char *file)
{
	struct sh2000_comp_status st;
	struct sh2000_comp_file *f = NULL;
	double scale[SH2000_AXES];
	char msg[512];
	size_t n;
	int r = sh2000_comp_status(c->h, &st);

	if (r < 0)
		return sh2000_tool_fail(c->h, r, "comp show");
	printf("tables: %s, %u table(s), id 0x%08x, sum 0x%08x, switch %u\n",
	       state_name(st.state), st.tables, st.id, st.sum, st.generation);
	if (!file)
		return 0;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if ((r = sh2000_param_get(c->h, (int)a, SH2000_P_SCALE, &scale[a])) < 0)
			return sh2000_tool_fail(c->h, r, "comp show");
	r = sh2000_comp_file_read(&f, file, scale, msg, sizeof(msg));
	if (r < 0) {
		sh2000_tool_msg("%s", msg);
		/* errors in the table; one that cannot be read is any tool's 1 */
		return r == -SH2000_EPARAM ? SH2000_EXIT_INPUT : SH2000_EXIT_CARD;
	}
	const uint16_t *w = sh2000_comp_file_image(f, &n);
	uint32_t sum = sh2000_comp_sum(w, n);

	printf("%s: sum 0x%08x: %s\n", file, sum,
	       st.state != SH2000_COMP_NONE && sum == st.sum ?
	       "the active tables" : "not active");
	sh2000_comp_file_free(f);
	return 0;
}

int ctl_comp(struct ctl *c, int argc, char **argv)
{
	const char *what = argc > 1 ? argv[1] : NULL;
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	if (!what || (strcmp(what, "load") && strcmp(what, "show") &&
		      strcmp(what, "clear")))
		return sh2000_tool_usage(argv[0], "comp: want load FILE, show [FILE] or clear");
	if ((!strcmp(what, "load") && argc != 3) || (!strcmp(what, "show") && argc > 3) ||
	    (!strcmp(what, "clear") && argc != 2))
		return sh2000_tool_usage(argv[0], "comp %s: %s", what,
					 !strcmp(what, "load") ? "one FILE" :
					 !strcmp(what, "show") ? "at most one FILE" :
					 "no argument");
	if ((r = ctl_open(c)))
		return r;
	if (!strcmp(what, "show"))
		return show(c, argc == 3 ? argv[2] : NULL);
	if (!strcmp(what, "clear")) {
		r = sh2000_comp_clear(c->h);
		return r < 0 ? sh2000_tool_fail(c->h, r, "comp clear") : 0;
	}
	r = sh2000_comp_load_file(c->h, argv[2]);
	if (r == -SH2000_EPARAM || r == -SH2000_ECMD_VALUE || r == -SH2000_ECMD_CHECKSUM) {
		sh2000_tool_msg("%s: nothing changed on the card", sh2000_last_error(c->h));
		return SH2000_EXIT_INPUT;
	}
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "comp load");
	r = show(c, NULL);
	return r ? r : ctl_comp_reach(c, argv[2]);
}
