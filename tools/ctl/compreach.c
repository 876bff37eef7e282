// SPDX-License-Identifier: MIT
/*
 * sh2000ctl comp load: how far the loaded tables move each axis inside
 * its soft limits, and a warning where the corrected position at a soft
 * limit lies beyond it (docs/compensation.md "Soft limits and the
 * corrections"). The judgement and its words are the library's
 * (sh2000_comp_reach_file(), over sh2000_comp_reach()); this prints them.
 */
#include <errno.h>

#include <sh2000/sh2000_protocol.h>

#include "ctl.h"

int ctl_comp_reach(struct ctl *c, const char *file)
{
	struct sh2000_comp_reach reach[SH2000_AXES];
	struct sh2000_comp_window win;
	char msg[512];
	int r = sh2000_comp_reach_file(c->h, file, &win, reach);

	if (r == -SH2000_EPARAM || r == -ENOENT || r == -EISDIR)
		return 0;	/* loaded a moment ago: nothing to say */
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "comp load");
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double k = win.scale[a];

		if (!reach[a].tables)
			continue;
		printf("axis %c: the tables correct it by %+.6f..%+.6f mm inside the soft limits\n",
		       sh2000_tool_axis_name(a), reach[a].lo / k, reach[a].hi / k);
		for (unsigned int side = 0; side < 2; side++)
			if (sh2000_comp_reach_warning(&win, reach, a, side, msg,
						      sizeof(msg)) > 0)
				sh2000_tool_msg("warning: %s", msg);
	}
	return 0;
}
