/* SPDX-License-Identifier: MIT */
/*
 * A bounded test move of one axis (testmove.h): shared by the step test
 * and the identification's excitation. Bounds first, nothing moved when
 * one is broken; during the test the card's following-error limit and DAC
 * limit are lowered to the user's, so the carriage stays within the
 * motion plus that following error and the DAC within its bound.
 * Afterwards, whatever happened, the limits are put back; after a
 * following-error fault the card is reset, the axis enabled again and
 * moved back to where it started by the planner (libsh2000-motion's
 * runner).
 */
#include <math.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

#include "testmove.h"

/* The way back after a fault: this share of the velocity bound and of the
 * axis' acceleration. */
#define RECOVER_SLOWER 0.1

int tune_move_fail(struct tune_move *s, int r, const char *what)
{
	return sh2000_tool_fail(s->h, r, what);
}

/* n coarse points, the axis at v[i] (every one at v[0] when step is 0),
 * in batches the ring has room for. */
static int push(struct tune_move *s, const int32_t *v, size_t step,
		size_t n, unsigned int flags)
{
	int32_t pts[32][SH2000_AXES];
	int r = 0;

	while (n) {
		size_t k = n < 32 ? n : 32;

		for (size_t i = 0; i < k; i++) {
			memcpy(pts[i], s->p, sizeof(pts[i]));
			pts[i][s->a] = v[i * step];
		}
		r = sh2000_wait_space(s->h, (unsigned int)k, 5000);
		if (r >= 0)
			r = sh2000_push_counts(s->h, (const int32_t (*)[SH2000_AXES])pts,
					       (unsigned int)k, k == n ? flags : 0);
		if (r < 0)
			return r;
		n -= k;
		v += k * step;
	}
	return 0;
}

int tune_move_hold(struct tune_move *s, int32_t v, unsigned int n,
		   unsigned int flags)
{
	return push(s, &v, 0, n, flags);
}

int tune_move_points(struct tune_move *s, const int32_t *v, size_t n,
		     unsigned int flags)
{
	return push(s, v, 1, n, flags);
}

/* The card idle and unfaulted, the axis enabled (by us with --enable),
 * the planner's configuration and every axis' set-point taken. */
int tune_move_begin(struct tune_move *s)
{
	char an = sh2000_tool_axis_name(s->a);
	struct sh2000_status st;
	int r;

	if ((r = sh2000_poll(s->h, &st)) < 0 || (r = sh2000_status_error(s->h, &st)) < 0)
		return tune_move_fail(s, r, "cannot test");
	if (st.card_state != SH2000_STATE_IDLE) {
		sh2000_tool_msg("%s: card is %s, not idle: nothing moved",
				sh2000_device(s->h), sh2000_state_name(st.card_state));
		return SH2000_EXIT_CARD;
	}
	if (!(st.axis[s->a].state & SH2000_AXIS_ENABLED)) {
		if (!s->o->enable) {
			sh2000_tool_msg("%s: axis %c is not enabled (sh2000ctl enable %c, or --enable): nothing moved",
					sh2000_device(s->h), an, an);
			return SH2000_EXIT_CARD;
		}
		if ((r = sh2000_enable(s->h, 1u << s->a)) < 0)
			return tune_move_fail(s, r, "enable");
		s->enabled_by_us = 1;
		if ((r = sh2000_poll(s->h, &st)) < 0)
			return tune_move_fail(s, r, "status");
	}
	if ((r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return tune_move_fail(s, r, "get parameter");
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		s->p[a] = (int32_t)st.axis[a].cmd_counts;
	s->start = s->p[s->a];
	return 0;
}

void tune_move_end(struct tune_move *s)
{
	if (s->enabled_by_us)
		sh2000_disable(s->h, 1u << s->a);
	s->enabled_by_us = 0;
}

double tune_move_vmax(const struct tune_move *s)
{
	double vlim = s->pc.vmax[s->a];

	if (s->o->vmax > 0 && s->o->vmax < vlim)
		vlim = s->o->vmax;
	return vlim;
}

/* The user's following-error and DAC bounds on the card, all or none. */
int tune_move_limits(struct tune_move *s)
{
	double ferr, dac;
	int r;

	if ((r = sh2000_param_get(s->h, s->a, SH2000_P_FERR_LIMIT, &s->ferr0)) < 0 ||
	    (r = sh2000_param_get(s->h, s->a, SH2000_P_DAC_LIMIT, &s->dac0)) < 0)
		return tune_move_fail(s, r, "get parameter");
	ferr = s->o->ferr_max_mm < s->ferr0 ? s->o->ferr_max_mm : s->ferr0;
	dac = s->o->dac_max > 0 && s->o->dac_max < s->dac0 ? s->o->dac_max : s->dac0;
	r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, ferr);
	if (r >= 0) {
		r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, dac);
		if (r < 0)
			sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0);
	}
	return r < 0 ? tune_move_fail(s, r, "set parameter") : 0;
}

/* After a fault: reset, limits back, the axis enabled and at its start. */
int tune_move_recover(struct tune_move *s, int fault, const char *test)
{
	struct sh2000_run_config rc;
	struct sh2000_run *run = NULL;
	double target[SH2000_AXES];
	char err[512] = "";
	int r;

	sh2000_tool_msg("%s: %s aborted: %s (limit %g mm during the test); returning to the start",
			sh2000_device(s->h), test, sh2000_strerror(fault),
			s->o->ferr_max_mm < s->ferr0 ? s->o->ferr_max_mm : s->ferr0);
	if ((r = sh2000_reset(s->h)) < 0 ||
	    (r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0)) < 0 ||
	    (r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, s->dac0)) < 0 ||
	    (r = sh2000_enable(s->h, 1u << s->a)) < 0 ||
	    (r = sh2000_run_path_config(s->h, &s->pc)) < 0)
		return tune_move_fail(s, r, "recovering");
	/* gently: the gains that just faulted may be far off */
	s->pc.amax[s->a] *= RECOVER_SLOWER;
	sh2000_run_config_default(&rc);
	r = sh2000_run_create(&run, s->h, &s->pc, &rc, err, sizeof(err));
	if (r < 0) {
		sh2000_tool_msg("%s", err);
		return sh2000_tool_exit_code(r);
	}
	memcpy(target, s->pc.start, sizeof(target));
	target[s->a] = s->start / s->pc.counts_per_mm[s->a];
	r = sh2000_path_move_abs(sh2000_run_path(run), target,
				 tune_move_vmax(s) * RECOVER_SLOWER);
	if (r >= 0)
		r = sh2000_run_finish(run);
	if (r < 0)
		sh2000_tool_msg("%s", sh2000_run_error(run));
	sh2000_run_destroy(run);
	return r < 0 ? sh2000_tool_exit_code(r) : TUNE_EXIT_ABORTED;
}

int tune_move_restore(struct tune_move *s)
{
	int r = sh2000_param_set(s->h, s->a, SH2000_P_FERR_LIMIT, s->ferr0);

	if (r >= 0)
		r = sh2000_param_set(s->h, s->a, SH2000_P_DAC_LIMIT, s->dac0);
	return r < 0 ? tune_move_fail(s, r, "restoring the limits") : 0;
}
