// SPDX-License-Identifier: MIT
/*
 * The sides of the card's gantry pair (gantry_pair, protocol 1.7) drive
 * one beam: a motion must move them by the same distance, as LinuxCNC
 * does when it drives both joints from one axis. The card cannot see
 * otherwise: its skew is the difference of the sides' following errors,
 * the coupling loop's work, not the beam's squareness, so a motion of one
 * side alone twists the beam with the DACs fighting until a fault ends
 * it (docs/protocol.md 12). So every planned point is judged here, in the
 * first pass of a program (nothing moves when a block breaks it) and in
 * the runner (a jog or move is refused at its first point, before
 * anything is pushed).
 *
 * The distances count from where each motion begins (the sides may stand
 * apart by the beam's squaring); they may differ by one count of the
 * coarser side: the planner moves both by the same millimetres, and the
 * card rounds each to its own count.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pair.h"
#include "sh2000/sh2000.h"

void sh2000_pair_rule_init(struct sh2000_pair_rule *p,
			   const struct sh2000_path_config *pc)
{
	unsigned int i, n = 0, ax[2] = { 0, 0 };

	memset(p, 0, sizeof(*p));
	for (i = 0; i < SH2000_AXES; i++)
		if (pc->gantry_pair & (1u << i)) {
			if (n < 2)
				ax[n] = i;
			n++;
		}
	if (n != 2)
		return;
	p->on = 1;
	p->a = ax[0];
	p->b = ax[1];
	p->tol_mm = 1.0 / fmin(pc->counts_per_mm[ax[0]] > 0 ?
			       pc->counts_per_mm[ax[0]] : 1e5,
			       pc->counts_per_mm[ax[1]] > 0 ?
			       pc->counts_per_mm[ax[1]] : 1e5);
}

int sh2000_pair_rule_point(const struct sh2000_pair_rule *p,
			   const double rest[SH2000_AXES],
			   const double mm[SH2000_AXES], char *msg, size_t len)
{
	static const char name[] = SH2000_AXIS_LETTERS;
	double da, db;

	if (!p->on)
		return 0;
	da = mm[p->a] - rest[p->a];
	db = mm[p->b] - rest[p->b];
	if (fabs(da - db) <= p->tol_mm)
		return 0;
	if (msg && len)
		snprintf(msg, len,
			 "%c and %c are one gantry beam (gantry_pair): here %c has moved %.6f mm and %c %.6f mm since the motion began, %.6f mm apart; move them together, by the same distance",
			 name[p->a], name[p->b], name[p->a], da, name[p->b], db,
			 fabs(da - db));
	return -SH2000_EGANTRY;
}
