// SPDX-License-Identifier: MIT
/* Program blocks (program.h) as planner primitives (sh2000/path.h). */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/path.h"
#include "sh2000/program.h"

static int add_arc(struct sh2000_path *p, const struct sh2000_prog_block *b)
{
	const struct sh2000_prog_arc *a = &b->u.arc;
	struct sh2000_path_arc pa;

	memset(&pa, 0, sizeof(pa));
	memcpy(pa.end, b->end, sizeof(pa.end));
	pa.radius_form = 0;
	pa.turns = a->turns > 0 ? a->turns - 1 : 0;
	/*
	 * The program's planes are right-handed (G18 is Z then X); the
	 * planner's XZ is X then Z, so its sense turns the other way there.
	 * The fitted centre is a true circle through both ends.
	 */
	switch (a->plane) {
	case SH2000_PROG_XY:
		pa.plane = SH2000_PLANE_XY;
		pa.centre[0] = a->fit_centre[SH2000_PROG_X];
		pa.centre[1] = a->fit_centre[SH2000_PROG_Y];
		pa.ccw = a->ccw;
		break;
	case SH2000_PROG_XZ:
		pa.plane = SH2000_PLANE_XZ;
		pa.centre[0] = a->fit_centre[SH2000_PROG_X];
		pa.centre[1] = a->fit_centre[SH2000_PROG_Z];
		pa.ccw = !a->ccw;
		break;
	case SH2000_PROG_YZ:
		pa.plane = SH2000_PLANE_YZ;
		pa.centre[0] = a->fit_centre[SH2000_PROG_Y];
		pa.centre[1] = a->fit_centre[SH2000_PROG_Z];
		pa.ccw = a->ccw;
		break;
	default:
		return -EINVAL;
	}
	return sh2000_path_arc(p, &pa, b->feed);
}

int sh2000_path_add_block(struct sh2000_path *p,
			   const struct sh2000_prog_block *b)
{
	struct sh2000_path_nurbs n;

	switch (b->kind) {
	case SH2000_PROG_RAPID:
		return sh2000_path_move_abs(p, b->end, 0.0);
	case SH2000_PROG_LINE:
		return sh2000_path_line(p, b->end, b->feed);
	case SH2000_PROG_ARC:
		return add_arc(p, b);
	case SH2000_PROG_NURBS:
		n.degree = b->u.nurbs.degree;
		n.count = (unsigned int)b->u.nurbs.npoints;
		n.ctrl = (const double (*)[SH2000_AXES])b->u.nurbs.points;
		n.weights = b->u.nurbs.weights;
		n.knots = b->u.nurbs.knots;
		return sh2000_path_nurbs(p, &n, b->feed);
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
