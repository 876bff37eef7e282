// SPDX-License-Identifier: MIT
/*
 * The look-ahead window: a ring of blocks. Queueing a block sets its
 * junction speed; a block's entry limit is local (its junction and the
 * feeds on both sides) and the controller checks every limit ahead from
 * its exact state, so there is no backward pass to redo when a block
 * comes; in a chain of short blocks the limits are held flat (no rise
 * shorter than CHAIN_PERIODS), and a short blend holds the lower limit
 * it ends on from its start. Dropping blocks (a stop, a reset)
 * releases the curves they refer to.
 */
#include <math.h>
#include <string.h>

#include "planner.h"

/* A block shorter than this many periods at its speed is one of a chain,
 * and a limit in a chain holds at least this long (chain_open()). At 2.5
 * zigzags of 0.2 to 0.25 mm moves turning +-10 degrees reached 1.054
 * amax; at 4 ten zigzags, S-bends and spirals of 0.25 to 1.5 mm moves
 * turning 20 to 45 degrees passed amax that kept within it before. */
#define CHAIN_PERIODS 3.0
/* The most blocks back from the tail a chain's limits are bounded over. */
#define CHAIN_BACK 16u

static void push_one(struct sh2000_path *p, struct pl_block *b);
static void bound_back(struct sh2000_path *p, unsigned int i);
static void chain_open(struct sh2000_path *p);
static void chain_fall(struct sh2000_path *p);

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

/* The entry limit of block k that the chain bounds: its junction's and
 * its own. */
static double chain_level(const struct pl_block *k)
{
	return pl_min(k->vj, k->vlim);
}

/* Whether the controller, from its state, can still brake to v before
 * block i (i >= 1) with room to spare: a limit it has not yet checked. */
static int chain_can_lower(const struct sh2000_path *p, unsigned int i,
			   double v)
{
	double T = p->cfg.period_s, vup = p->v + p->a_top * T, d = -p->s;
	unsigned int q;

	if (p->qi < p->qn)	/* a landing under way: leave its target */
		return 0;
	for (q = 0; q < i; q++)
		d += pl_block_at(p, q)->L;
	return d > 2.0 * pl_brake_dist(&p->lim, vup, p->a_top, v) +
		   4.0 * T * vup;
}

/* Block i's own limit down to v, its acceleration with it, and the next
 * block's copy of that limit (the tail's, past the last). */
static void chain_lower(struct sh2000_path *p, unsigned int i, double v)
{
	struct pl_block *k = (struct pl_block *)pl_block_at(p, i);

	k->vlim = v;
	k->A = pl_block_accel(p, k);
	if (i + 1 < p->count)
		((struct pl_block *)pl_block_at(p, i + 1))->prev_vlim = v;
	else
		p->tail_vlim = v;
}

/*
 * The chain of short blocks ending at the tail, at most CHAIN_BACK back
 * and never the head: the ring index of its first block, and each
 * block's level into f[]. Returns how many.
 */
static unsigned int chain_collect(const struct sh2000_path *p,
				  unsigned int *first, double f[CHAIN_BACK])
{
	double T = p->cfg.period_s;
	unsigned int n = 0, i = p->count;

	while (i > 1 && n < CHAIN_BACK) {
		const struct pl_block *k = pl_block_at(p, i - 1);

		/* not an arc nor a blend of a turn of 45 degrees or more:
		 * with them, spirals of 0.1 mm moves turning 60 to 90
		 * degrees at G64 P0.01 reached 3 to 3.6 amax */
		if (k->corner || k->type == BLK_NURBS ||
		    (k->type != BLK_LINE && !pl_accel_dyn(k)) ||
		    !(k->L < CHAIN_PERIODS * T * chain_level(k)))
			break;
		i--;
		n++;
	}
	*first = i;
	for (i = 0; i < n; i++)
		f[i] = chain_level(pl_block_at(p, *first + i));
	return n;
}

/*
 * In a chain of blocks each shorter than CHAIN_PERIODS at its speed, a
 * limit may rise only where it holds for CHAIN_PERIODS (the morphological
 * opening of the entry limits over that span): the controller cruises
 * through the chain instead of speeding up and braking in every block,
 * which swings the acceleration within a period or two. What lies past
 * the tail is not known yet, so it counts as no limit: a limit only
 * falls as blocks come, and falls only where the controller can still
 * brake to it.
 */
static void chain_open(struct sh2000_path *p)
{
	double f[CHAIN_BACK], o[CHAIN_BACK], T = p->cfg.period_s;
	unsigned int n, first, j, m;

	if (p->cfg.output != SH2000_OUTPUT_COMPENSATED)
		return;
	n = chain_collect(p, &first, f);
	for (j = 0; j < n; j++)
		o[j] = 0.0;
	for (j = 0; j < n; j++) {	/* the window from block j's start */
		double w = f[j], d = 0.0;

		for (m = j; m < n; m++) {
			if (m > j && !(d < CHAIN_PERIODS * T * pl_min(w, f[m])))
				break;
			w = pl_min(w, f[m]);
			d += pl_block_at(p, first + m)->L;
		}
		while (m-- > j)
			o[m] = pl_max(o[m], w);
	}
	for (j = n; j-- > 0;) {
		unsigned int i = first + j;
		const struct pl_block *k = pl_block_at(p, i);

		/* the limit inside the block, not only at its entry (a
		 * blend entered at 15.7 mm/s whose own limit stayed at 36
		 * sped up to 29 in 0.12 mm, braked into the next block's
		 * and reached 1.77 amax); a block longer than the span at
		 * that speed keeps its own */
		if (!(o[j] < k->vlim) ||
		    !(k->L < CHAIN_PERIODS * T * o[j]))
			continue;
		if (!chain_can_lower(p, i, o[j]))
			return;
		chain_lower(p, i, o[j]);
	}
}

/*
 * A short blend whose exit limit (the next block's entry: a curvature
 * step into a line, a slower block) is lower than its entry holds the
 * lower one from its entry: braking to the entry's and at once again
 * inside the blend swung the acceleration by some 4000 mm/s^2 in a period
 * (zigzags of 0.6 to 3 mm moves turning 10 degrees at G64 P0.01: 1.04 to
 * 1.08 amax on the card's set-points). Back from the tail block, as far
 * as such blends go; not lines (held so, the short lines of a CAM
 * surfacing program took 27 % longer), not to a corner's or a stop's
 * speed (a point's: a block's own limit of 0 is never passed).
 */
static void chain_fall(struct sh2000_path *p)
{
	double T = p->cfg.period_s;
	unsigned int i, n = 0;

	if (p->cfg.output != SH2000_OUTPUT_COMPENSATED)
		return;
	for (i = p->count - 1; i > 1 && n < CHAIN_BACK; i--, n++) {
		const struct pl_block *k = pl_block_at(p, i - 1);
		const struct pl_block *t = pl_block_at(p, i);
		double v = chain_level(t), top = chain_level(k);

		if (!pl_accel_dyn(k) || t->corner || !(v > 0.0) ||
		    !(v < top) || !(k->L < CHAIN_PERIODS * T * top) ||
		    !chain_can_lower(p, i - 1, v))
			return;
		chain_lower(p, i - 1, v);
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
	chain_open(p);
	chain_fall(p);
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
