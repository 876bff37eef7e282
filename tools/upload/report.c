// SPDX-License-Identifier: MIT
/*
 * Progress while the card runs: a bar redrawn in place when stderr is a
 * terminal, otherwise one plain line per 10 %.
 */
#include <stdio.h>
#include <time.h>

#include "upload.h"

static uint64_t wall_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

void upl_report_progress(struct upl_report *rp,
			 const struct sh2000_run_progress *p)
{
	uint64_t done = p->points > p->queue_fill ? p->points - p->queue_fill : 0;
	unsigned int line = 0;
	int pct;

	if (rp->quiet || !rp->total_points)
		return;
	if (done > rp->total_points)
		done = rp->total_points;
	pct = (int)(done * 100u / rp->total_points);
	/* the points' tag is their block's line (sh2000_run_program) */
	if (p->seq > 0 && p->seq <= (int64_t)UINT32_MAX)
		line = (unsigned int)p->seq;
	if (rp->bar) {
		uint64_t now = wall_ns();
		char bar[41];
		int i, fill = pct * 40 / 100;

		if (now - rp->last_ns < 100000000ull && pct != 100)
			return;
		rp->last_ns = now;
		for (i = 0; i < 40; i++)
			bar[i] = i < fill ? '#' : '.';
		bar[40] = 0;
		fprintf(stderr, "\r[%s] %3d%%  %7.2f s  line %-6u queue %2u ",
			bar, pct, p->t, line, p->queue_fill);
		rp->last_pct = pct;
		return;
	}
	if (pct / 10 > rp->last_pct / 10 || (rp->last_pct < 0 && pct >= 0)) {
		if (line)
			fprintf(stderr, "%s: progress %3d%% (%.2f s, line %u)\n",
				sh2000_tool_name(), pct / 10 * 10, p->t, line);
		else
			fprintf(stderr, "%s: progress %3d%% (%.2f s)\n",
				sh2000_tool_name(), pct / 10 * 10, p->t);
		rp->last_pct = pct;
	}
}

void upl_report_end(struct upl_report *rp)
{
	if (rp->bar && !rp->quiet && rp->last_ns)
		fputc('\n', stderr);
	rp->last_ns = 0;
}
