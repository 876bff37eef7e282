/* SPDX-License-Identifier: MIT */
/*
 * Running the planner's points through libsh2000's in-process `sim` card
 * (protocol, firmware fine interpolation, PID, plant), for the planner's
 * card test and benchmark: a sink that pushes batches through the
 * library's segment push, and a servo-cycle observer that hands every fine
 * set-point and encoder position to a callback. Header-only, one copy.
 */
#ifndef SH2000_PLCARD_H
#define SH2000_PLCARD_H

#include <stdio.h>
#include <string.h>

#include "sh2000/path.h"
#include "sh2000/sh2000.h"
#include "sh2000/sim.h"

typedef void (*plcard_fine_fn)(void *ctx, const double cmd[4],
			       const double act[4]);

struct plcard {
	struct sh2000 *h;
	double batch[16][SH2000_AXES];
	unsigned int nb;
	int err;
	double scale;
	int record;
	plcard_fine_fn fn;
	void *ctx;
	char msg[256];
};

static inline int plcard_flush(struct plcard *pc, int end)
{
	int r;

	if (!pc->nb)
		return 0;
	r = sh2000_wait_space(pc->h, pc->nb, 5000);
	if (r >= 0)
		r = sh2000_push_mm(pc->h, (const double (*)[4])pc->batch,
				   pc->nb, end ? SH2000_PUSH_END : 0);
	pc->nb = 0;
	if (r < 0) {
		pc->err = r;
		snprintf(pc->msg, sizeof(pc->msg), "push: %s (%s)",
			 sh2000_strerror(r), sh2000_last_error(pc->h));
		return r;
	}
	return 0;
}

static inline int plcard_sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct plcard *pc = ctx;
	int end = (pt->flags & SH2000_PATH_F_END) != 0;

	memcpy(pc->batch[pc->nb++], pt->mm, sizeof(pt->mm));
	if (end || pc->nb == 16)
		return plcard_flush(pc, end);
	return 0;
}

static inline void plcard_obs(void *ctx, const struct sh2000_probe *pr)
{
	struct plcard *pc = ctx;
	double cmd[4], act[4];
	unsigned int a;

	if (!pc->record || !pc->fn)
		return;
	for (a = 0; a < 4; a++) {
		cmd[a] = pr->axis[a].fine_cmd / pc->scale;
		act[a] = pr->axis[a].actual / pc->scale;
	}
	pc->fn(pc->ctx, cmd, act);
}

#define PLCARD_TRY(pc, call) do { int r_ = (call); if (r_ < 0) { \
	snprintf((pc)->msg, sizeof((pc)->msg), "%s: %s (%s)", #call, \
		 sh2000_strerror(r_), sh2000_last_error((pc)->h)); \
	return r_; } } while (0)

/* Open `sim`, 2 ms / 20 fine steps, the planner's vmax and amax on the
 * card, feed-forward on or off, all axes enabled; *start gets the card's
 * set-point (where a planner must start). */
static inline int plcard_open(struct plcard *pc, const double vmax[4],
			      const double amax[4], int ff, double start[4])
{
	struct sh2000_status st;
	unsigned int a;
	int r;

	memset(pc, 0, sizeof(*pc));
	pc->scale = 100000.0;	/* the plant's and the card's default */
	r = sh2000_sim_open(&pc->h, NULL, pc->msg, sizeof(pc->msg));
	if (r < 0)
		return r;
	PLCARD_TRY(pc, sh2000_param_set(pc->h, SH2000_GLOBAL,
					SH2000_GP_COARSE_PERIOD_US, 2000));
	PLCARD_TRY(pc, sh2000_param_set(pc->h, SH2000_GLOBAL,
					SH2000_GP_FINE_STEPS, 20));
	for (a = 0; a < 4; a++) {
		PLCARD_TRY(pc, sh2000_param_set(pc->h, a, SH2000_P_VMAX, vmax[a]));
		PLCARD_TRY(pc, sh2000_param_set(pc->h, a, SH2000_P_AMAX, amax[a]));
		if (!ff) {
			PLCARD_TRY(pc, sh2000_param_set(pc->h, a, SH2000_P_KVFF, 0));
			PLCARD_TRY(pc, sh2000_param_set(pc->h, a, SH2000_P_KAFF, 0));
		}
	}
	PLCARD_TRY(pc, sh2000_enable(pc->h, 0xf));
	PLCARD_TRY(pc, sh2000_poll(pc->h, &st));
	for (a = 0; a < 4; a++)
		start[a] = st.axis[a].cmd_mm;
	PLCARD_TRY(pc, sh2000_sim_set_observer(pc->h, plcard_obs, pc));
	return 0;
}

/* After the planner finished: wait for the card to come to rest. */
static inline int plcard_idle(struct plcard *pc)
{
	if (pc->err)
		return pc->err;
	PLCARD_TRY(pc, sh2000_wait_idle(pc->h, 20000));
	return 0;
}

static inline void plcard_close(struct plcard *pc)
{
	sh2000_close(pc->h);
	pc->h = NULL;
}

#endif /* SH2000_PLCARD_H */
