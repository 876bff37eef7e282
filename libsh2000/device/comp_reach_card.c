// SPDX-License-Identifier: MIT
/*
 * A table file's reach on a card: the card's soft limits and scales as
 * the window of sh2000_comp_reach() (libsh2000/protocol/comp_reach.c, the
 * one owner of the judgement), the file read with the card's scales. The
 * front ends that put tables on a card (sh2000ctl comp load, hal_sh2000's
 * comp=, sh2000-comp csv) call this after their load or check.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>

#include "sh2000_internal.h"

/* The card's SOFT_MIN and SOFT_MAX back in its counts (the library's
 * parameters are in mm), its off values kept exactly. */
static int32_t to_counts(double mm, double scale)
{
	double c = nearbyint(mm * scale);

	return c <= (double)INT32_MIN ? INT32_MIN :
	       c >= (double)INT32_MAX ? INT32_MAX : (int32_t)c;
}

static int window_get(struct sh2000 *h, struct sh2000_comp_window *win)
{
	*win = (struct sh2000_comp_window){ 0 };
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double lo, hi;
		int r = sh2000_param_get(h, (int)a, SH2000_P_SCALE, &win->scale[a]);

		if (!r)
			r = sh2000_param_get(h, (int)a, SH2000_P_SOFT_MIN, &lo);
		if (!r)
			r = sh2000_param_get(h, (int)a, SH2000_P_SOFT_MAX, &hi);
		if (r < 0)
			return r;
		win->soft_min[a] = to_counts(lo, win->scale[a]);
		win->soft_max[a] = to_counts(hi, win->scale[a]);
	}
	return 0;
}

int sh2000_comp_reach_file(struct sh2000 *h, const char *path,
			   struct sh2000_comp_window *win,
			   struct sh2000_comp_reach reach[SH2000_AXES])
{
	struct sh2000_comp_file *f = NULL;
	struct sh2000_comp_index ix;
	struct sh2000_comp_fault why;
	const uint16_t *w;
	char msg[512];
	size_t n;
	int r;

	if (!h || !path || !win || !reach)
		return -EINVAL;
	r = window_get(h, win);
	if (r < 0)
		return r;
	snprintf(msg, sizeof(msg), "%s: cannot be read", path);
	r = sh2000_comp_file_read(&f, path, win->scale, msg, sizeof(msg));
	if (r < 0)
		return sh2000_fail(h, r, "%s", msg);
	w = sh2000_comp_file_image(f, &n);
	if (sh2000_comp_parse(w, n, &ix, &why) < 0)
		r = sh2000_fail(h, -SH2000_EPARAM, "%s",
				sh2000_comp_file_explain(f, &why, msg, sizeof(msg)));
	else
		r = sh2000_comp_reach(w, &ix, win, reach);
	sh2000_comp_file_free(f);
	return r;
}
