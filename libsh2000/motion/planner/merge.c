// SPDX-License-Identifier: MIT
/*
 * LinuxCNC's naive CAM detector (G64 P Q): a run of straight feed moves
 * at one feed whose corners all lie within Q of a single line is taken as
 * that line. CAM output approximates smooth curves and straight edges by
 * many tiny moves; merging them gives the planner long blocks to move
 * fast on, and keeps the path within Q of every programmed point.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

/* The tail as a line from its start to end, every merged point within
 * tol of it. */
static int fits(const struct sh2000_path *p, const struct pl_block *t,
		const double end[SH2000_AXES], double tol)
{
	unsigned int i;

	if (pl_seg_dist(t->p1, t->p0, end) > tol)
		return 0;
	for (i = 0; i < p->merged_n; i++)
		if (pl_seg_dist(p->merged[i], t->p0, end) > tol)
			return 0;
	return 1;
}

int pl_merge_line(struct sh2000_path *p, const struct pl_block *b)
{
	double tol = p->cfg.naive_tol, len = 0.0;
	struct pl_block *t;
	unsigned int a;

	if (b->type != BLK_LINE || !(tol > 0.0) || p->stop_next ||
	    p->cfg.mode != SH2000_PATH_BLEND || !p->count ||
	    (p->count == 1 && p->moving) || p->merged_n >= PL_MERGE_MAX)
		return 0;
	t = (struct pl_block *)pl_block_at(p, p->count - 1);
	if (t->type != BLK_LINE || t->stop_after || t->feed != b->feed ||
	    memcmp(t->p1, b->p0, sizeof(t->p1)) || !fits(p, t, b->p1, tol))
		return 0;
	memcpy(p->merged[p->merged_n++], t->p1, sizeof(t->p1));
	for (a = 0; a < SH2000_AXES; a++)
		len += (b->p1[a] - t->p0[a]) * (b->p1[a] - t->p0[a]);
	len = sqrt(len);
	memcpy(t->p1, b->p1, sizeof(t->p1));
	t->L = len;
	for (a = 0; a < SH2000_AXES; a++)
		t->g.line.d[a] = t->t0[a] = t->t1[a] = (t->p1[a] - t->p0[a]) / len;
	t->vlim = pl_curve_vlim(p, t->t0, 0.0);
	/* the corner into it turned a little: its junction again */
	if (p->count >= 2 && t->vj != 0.0)
		t->vj = pl_junction(p, pl_block_at(p, p->count - 2)->t1, t->t0);
	t->corner = !isinf(t->vj);
	memcpy(p->tend, t->t1, sizeof(p->tend));
	memcpy(p->qend, t->p1, sizeof(p->qend));
	p->tail_vlim = t->vlim;
	return 1;
}
