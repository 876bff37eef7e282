// SPDX-License-Identifier: MIT
/* Program blocks (program.h) as planner primitives (sh2000/path.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/path.h"
#include "sh2000/program.h"

/*
 * The arc as the program has it: its centre, and a radius that may change
 * from start to end within LinuxCNC's rule (geometry.h), which LinuxCNC
 * runs as a spiral whose radius changes with the angle; the planner's arcs
 * are that spiral (sh2000_arc_point). The reader has already judged the
 * difference of the radii against its tolerance: the planner is given
 * that difference as its own. A circle fitted through both ends instead
 * leaves the spiral by far more than the difference on a long arc (163 um
 * for 30 um on 350 degrees).
 */
static int add_arc(struct sh2000_path *p, const struct sh2000_prog_block *b)
{
	const struct sh2000_arc *a = &b->u.arc;
	struct sh2000_path_arc pa;

	memset(&pa, 0, sizeof(pa));
	memcpy(pa.end, b->end, sizeof(pa.end));
	pa.plane = a->plane;
	pa.centre[0] = a->centre[0];
	pa.centre[1] = a->centre[1];
	pa.ccw = a->ccw;
	pa.turns = a->turns;
	pa.tolerance = fabs(a->r1 - a->r0) * (1.0 + 1e-9);
	return sh2000_path_arc(p, &pa, b->feed);
}

int sh2000_path_add_block(struct sh2000_path *p,
			   const struct sh2000_prog_block *b)
{
	switch (b->kind) {
	case SH2000_PROG_RAPID:
		return sh2000_path_rapid(p, b->end);
	case SH2000_PROG_LINE:
		return sh2000_path_line(p, b->end, b->feed);
	case SH2000_PROG_ARC:
		return add_arc(p, b);
	case SH2000_PROG_NURBS:
		return sh2000_path_nurbs(p, &b->u.nurbs, b->feed);
	case SH2000_PROG_PATH_MODE:
		return sh2000_path_set_mode(p, b->u.path.mode,
					    b->u.path.tolerance,
					    b->u.path.naive_tolerance);
	default:
		return 0;
	}
}

int sh2000_prog_block_where(const struct sh2000_prog_block *b, char *buf,
			    size_t len)
{
	return snprintf(buf, len, "%s:%u:%u", b->pos.file ? b->pos.file : "?",
		 b->pos.line, b->pos.column);
}

unsigned int sh2000_prog_block_axes(const struct sh2000_prog_block *b,
				    const double at[SH2000_AXES])
{
	unsigned int a, m = 0;
	size_t i;

	switch (b->kind) {
	case SH2000_PROG_ARC:
		m = 1u << b->u.arc.first | 1u << b->u.arc.second;
		break;
	case SH2000_PROG_NURBS:
		for (i = 0; i < b->u.nurbs.npoints; i++)
			for (a = 0; a < SH2000_AXES; a++)
				if (b->u.nurbs.points[i][a] != at[a])
					m |= 1u << a;
		break;
	case SH2000_PROG_RAPID:
	case SH2000_PROG_LINE:
		break;
	default:
		return 0;
	}
	for (a = 0; a < SH2000_AXES; a++)
		if (b->end[a] != at[a])
			m |= 1u << a;
	return m;
}
