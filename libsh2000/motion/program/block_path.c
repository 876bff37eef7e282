// SPDX-License-Identifier: MIT
/* Program blocks (program.h) as planner primitives (sh2000/path.h). */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/path.h"
#include "sh2000/program.h"

/* The fitted centre: a true circle through both ends, which the
 * planner's arcs are. Plane, sense and turns are geometry.h's on both
 * sides. */
static int add_arc(struct sh2000_path *p, const struct sh2000_prog_block *b)
{
	const struct sh2000_arc *a = &b->u.arc;
	struct sh2000_path_arc pa;

	memset(&pa, 0, sizeof(pa));
	memcpy(pa.end, b->end, sizeof(pa.end));
	pa.plane = a->plane;
	pa.centre[0] = a->fit_centre[0];
	pa.centre[1] = a->fit_centre[1];
	pa.ccw = a->ccw;
	pa.turns = a->turns;
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
