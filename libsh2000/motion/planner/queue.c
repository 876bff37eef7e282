// SPDX-License-Identifier: MIT
/*
 * The look-ahead window: a ring of blocks. Queueing a block sets its
 * junction speed; a block's entry limit is local (its junction and the
 * feeds on both sides) and the controller checks every limit ahead from
 * its exact state, so there is no backward pass to redo when a block
 * comes. Dropping blocks (a stop, a reset) releases the curves they refer
 * to.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

static void push_one(struct sh2000_path *p, struct pl_block *b);
static void bound_back(struct sh2000_path *p, unsigned int i);

void pl_push_block(struct sh2000_path *p, struct pl_block *b)
{
	/* rapid to feed move or back: a stop, as in LinuxCNC's planner */
	if (b->rapid != p->tail_rapid)
		p->stop_next = 1;
	if (pl_merge_line(p, b))
		return;
	p->merged_n = 0;	/* a new last block */
	pl_push_blended(p, b);
}

void pl_push_blended(struct sh2000_path *p, struct pl_block *b)
{
	struct pl_block k[2];
	unsigned int n, i;

	n = pl_blend_corner(p, b, k);
	for (i = 0; i < n; i++) {
		k[i].rapid = b->rapid;
		push_one(p, &k[i]);
	}
	b->nblend = n;
	push_one(p, b);
	if (p->count >= n + 2)
		bound_back(p, p->count - n - 2);
}

/*
 * The speed the blocks before block i can leave them at, from i's entry
 * limits back (at no more than any block's acceleration), and the
 * accelerations that gives them (pl_block_accel()). Block i is the
 * programmed move before the last: the last one and the blends before it
 * may still be merged, cut or replaced (merge.c, blend.c), and i's end
 * moved, but i's start and everything before it no longer change. A
 * bound only falls, so an acceleration only grows.
 */
static void bound_back(struct sh2000_path *p, unsigned int i)
{
	const struct pl_block *b = pl_block_at(p, i);
	double x = pl_min(b->vj, b->vlim);
	unsigned int n;

	for (n = 0; n < PL_BOUND_BACK && i > 0; n++) {
		struct pl_block *k = (struct pl_block *)pl_block_at(p, --i);

		if (!(x < k->vout))
			return;
		k->vout = x;
		k->A = pl_block_accel(p, k);
		x = pl_min(pl_min(k->vj, k->vlim),
			   sqrt(x * x + 2.02 * p->a_top * k->L));
	}
}

void pl_unqueue_tail(struct sh2000_path *p)
{
	const struct pl_block *t = pl_block_at(p, p->count - 1);
	const struct pl_block *prev;

	p->count -= 1 + t->nblend;
	p->blocks -= 1 + t->nblend;
	prev = pl_block_at(p, p->count - 1);
	p->tail_feed = prev->feed;
	p->tail_vlim = prev->vlim;
	p->stop_next = prev->stop_after;
	p->tail_rapid = prev->rapid;
	memcpy(p->tend, prev->t1, sizeof(p->tend));
	memcpy(p->qend, prev->p1, sizeof(p->qend));
}

/* The last block queued ends at rest: a line that started at rest too
 * runs from rest to rest, where with one jerk a period the card's spline
 * is the plan itself (pl_block_accel()); one out of a curve is, past the
 * two periods after it (pl_ring_zone()). Its acceleration only grows,
 * so every limit the controller checked with the lower one still holds
 * (its zone's is the lower one). */
void pl_rest_after(struct sh2000_path *p)
{
	struct pl_block *t;

	if (!p->quant || !p->count)
		return;
	t = (struct pl_block *)pl_block_at(p, p->count - 1);
	if (t->type == BLK_LINE && (t->vj == 0.0 || t->ring_start) &&
	    !t->rest_line) {
		t->rest_line = 1;
		t->A = pl_block_accel(p, t);
	}
}

static void push_one(struct sh2000_path *p, struct pl_block *b)
{
	unsigned int i;
	double nt = 0.0;

	b->seq = p->seq;
	if (p->cfg.mode == SH2000_PATH_EXACT_STOP)
		b->stop_after = 1;
	for (i = 0; i < SH2000_AXES; i++)
		nt += p->tend[i] * p->tend[i];
	if (p->stop_next || nt < 0.5)
		b->vj = 0.0;
	else
		b->vj = pl_junction(p, p->tend, b->t0);
	b->corner = !isinf(b->vj);
	/* a tangent junction: where the curvature steps (not a corner: no
	 * zone of the corner's acceleration around it) */
	if (!b->corner && p->count)
		b->vj = pl_curv_step(p, pl_block_at(p, p->count - 1), b);
	/* through a line shorter than a period the card's spline sees one
	 * step, from the curvature before the line to this block's (two
	 * blends turning opposite ways across a 0.2 mm line: each junction
	 * bounded alone, the acceleration swung from -1476 to +2588 mm/s^2) */
	if (!b->corner && p->count >= 2) {
		const struct pl_block *q = pl_block_at(p, p->count - 1);

		if (q->type == BLK_LINE && !q->corner &&
		    q->L < p->cfg.period_s * pl_min(q->vlim, b->vlim))
			b->vj = pl_min(b->vj, pl_curv_step(p, pl_block_at(p, p->count - 2), b));
	}
	/* an empty window: the motion is at rest */
	b->vin = pl_min(b->vj, b->vlim);
	b->vin = p->count ? pl_min(b->vin, pl_fwd_exit(p, pl_block_at(
					p, p->count - 1))) : 0.0;
	b->vout = INFINITY;
	b->rest_line = 0;
	b->ring_start = b->type == BLK_LINE && !b->corner && p->count &&
			pl_block_at(p, p->count - 1)->type != BLK_LINE;
	if (b->vj == 0.0)
		pl_rest_after(p);
	b->A = pl_block_accel(p, b);
	if (b->feed == 0.0)
		b->feed = INFINITY;
	if (p->stop_next || !p->blocks) {
		b->prev_feed = b->feed;
		b->prev_vlim = b->vlim;
	} else {
		b->prev_feed = p->tail_feed;
		b->prev_vlim = p->tail_vlim;
	}
	p->tail_feed = b->feed;
	p->tail_vlim = b->vlim;
	p->stop_next = b->stop_after;
	p->tail_rapid = b->rapid;
	memcpy(p->tend, b->t1, sizeof(p->tend));
	memcpy(p->qend, b->p1, sizeof(p->qend));
	p->blk[(p->head + p->count) % p->cap] = *b;
	p->count++;
	p->blocks++;
	if (b->stop_after)
		pl_rest_after(p);
}

void pl_drop_blocks(struct sh2000_path *p)
{
	while (p->count) {
		struct pl_block *b = &p->blk[p->head];

		if (b->type == BLK_NURBS)
			pl_nurbs_put(p, b->g.nurbs.nb);
		p->head = (p->head + 1) % p->cap;
		p->count--;
	}
	if (p->pending) {
		struct pl_nurbs *nb = p->pending;

		p->pending = NULL;
		nb->expanded = 1;
		nb->refs++;
		pl_nurbs_put(p, nb);
	}
}

void pl_stopped(struct sh2000_path *p)
{
	pl_drop_blocks(p);
	memcpy(p->qend, p->pos, sizeof(p->qend));
	memset(p->tend, 0, sizeof(p->tend));
	p->stop_next = 1;
	p->stopping = 0;
	p->paused = 0;
	p->s = p->v = p->a = 0.0;
}
