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

/* The tail as a line from its programmed start to end, every merged point
 * within tol of it. */
static int fits(const struct sh2000_path *p, const struct pl_block *t,
		const double end[SH2000_AXES], double tol)
{
	unsigned int i;

	if (pl_seg_dist(t->p1, t->c0, end) > tol)
		return 0;
	for (i = 0; i < p->merged_n; i++)
		if (pl_seg_dist(p->merged[i], t->c0, end) > tol)
			return 0;
	return 1;
}

/* The line before the tail's blend, to be given back the end the blend
 * cut, or NULL when there is none: only a line can be, and not the block
 * the controller is in. */
static struct pl_block *line_before(struct sh2000_path *p,
				    const struct pl_block *t)
{
	struct pl_block *k;

	if (p->count < t->nblend + 3)
		return NULL;
	k = (struct pl_block *)pl_block_at(p, p->count - 2 - t->nblend);
	return k->type == BLK_LINE ? k : NULL;
}

/* Line k from its start to x. */
static void line_to(const struct sh2000_path *p, struct pl_block *k,
		    const double x[SH2000_AXES])
{
	double len = 0.0;
	unsigned int a;

	memcpy(k->p1, x, sizeof(k->p1));
	for (a = 0; a < SH2000_AXES; a++)
		len += (k->p1[a] - k->p0[a]) * (k->p1[a] - k->p0[a]);
	k->L = len = sqrt(len);
	for (a = 0; a < SH2000_AXES; a++)
		k->g.line.d[a] = k->t0[a] = k->t1[a] =
			(k->p1[a] - k->p0[a]) / len;
	k->vlim = pl_curve_vlim(p, k->t0, 0.0);
	k->A = pl_block_accel(p, k);
}

int pl_merge_line(struct sh2000_path *p, const struct pl_block *b)
{
	double tol = p->cfg.naive_tol;
	struct pl_block *t, *prev = NULL, m;

	if (b->type != BLK_LINE || b->rapid || !(tol > 0.0) || p->stop_next ||
	    p->cfg.mode != SH2000_PATH_BLEND || !p->count ||
	    (p->count == 1 && p->moving) || p->merged_n >= PL_MERGE_MAX)
		return 0;
	t = (struct pl_block *)pl_block_at(p, p->count - 1);
	if (t->type != BLK_LINE || t->stop_after || t->feed != b->feed ||
	    memcmp(t->p1, b->p0, sizeof(t->p1)) || !fits(p, t, b->p1, tol))
		return 0;
	/* a blended corner into it was made for its old direction: it is
	 * made again, from the programmed corner, for the new one */
	if (t->nblend && !(prev = line_before(p, t)))
		return 0;
	memcpy(p->merged[p->merged_n++], t->p1, sizeof(t->p1));
	m = *t;
	memcpy(m.p0, m.c0, sizeof(m.p0));
	line_to(p, &m, b->p1);
	if (prev) {
		line_to(p, prev, m.c0);
		pl_unqueue_tail(p);
		m.nblend = 0;
		pl_push_blended(p, &m);
		return 1;
	}
	*t = m;
	/* the corner into it turned a little: its junction again */
	if (p->count >= 2 && t->vj != 0.0)
		t->vj = pl_junction(p, pl_block_at(p, p->count - 2)->t1, t->t0);
	t->corner = !isinf(t->vj);
	memcpy(p->tend, t->t1, sizeof(p->tend));
	memcpy(p->qend, t->p1, sizeof(p->qend));
	p->tail_vlim = t->vlim;
	return 1;
}
