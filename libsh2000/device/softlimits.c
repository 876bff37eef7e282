/* SPDX-License-Identifier: MIT */
/*
 * The rule that new soft limits must not leave an enabled or homed axis
 * outside them. The card refuses every set-point outside its soft limits,
 * so an axis left outside could not move at all, not even back. One
 * judgement, in the card's counts, for every front end (sh2000.h):
 * sh2000_param_set(), sh2000_axis_params_set(), sh2000ctl's params plan,
 * Python through the library.
 */
#include <math.h>
#include <stdint.h>

#include "sh2000_internal.h"

/*
 * The judgement itself, on the window lo..hi in counts (as the card holds
 * it). The position that counts: an enabled axis' set-point (the card
 * holds it there), a homed axis' position; a disabled axis never homed is
 * not judged, where it is means nothing yet. Lengths in the message in mm
 * of `scale`, the scale the window goes with.
 */
static int judge(const struct sh2000_status *st, unsigned int axis,
		 double lo, double hi, double scale, char *why, size_t len)
{
	const struct sh2000_axis_status *ax = &st->axis[axis];
	int enabled = (ax->state & SH2000_AXIS_ENABLED) != 0;
	char a = sh2000_axis_letter((int)axis);
	double at;

	if (!enabled && !(ax->state & SH2000_AXIS_HOMED))
		return 0;
	at = enabled ? (double)ax->cmd_counts : (double)ax->pos_counts;
	if (at >= lo && at <= hi)
		return 0;
	return sh2000_msg(why, len, -SH2000_EPARAM,
			  "%c soft limits %g..%g mm would leave axis %c (%s, at %.4f mm) outside them: the card refuses every set-point outside its soft limits, so nothing could move it back; move it inside first, or give limits around it",
			  a, lo / scale, hi / scale, a,
			  enabled ? "enabled" : "homed", at / scale);
}

int sh2000_soft_limits_check(const struct sh2000_status *st, unsigned int axis,
			     double soft_min, double soft_max, double scale,
			     char *why, size_t len)
{
	if (!st || axis >= SH2000_AXES)
		return sh2000_msg(why, len, -SH2000_EPARAM,
				  "soft limits: no axis %u", axis);
	if (!isfinite(soft_min) || !isfinite(soft_max) || !isfinite(scale) ||
	    !(scale > 0.0))
		return sh2000_msg(why, len, -SH2000_EPARAM,
				  "%c soft limits %g..%g mm in %g counts/mm: not finite numbers with a scale above 0",
				  sh2000_axis_letter((int)axis), soft_min,
				  soft_max, scale);
	/* in counts, rounded as the card gets them (sh2000_param_value_check) */
	return judge(st, axis, nearbyint(soft_min * scale),
		     nearbyint(soft_max * scale), scale, why, len);
}

int sh2000_soft_limits_locked(struct sh2000 *h, int axis, const char *what,
			      int32_t lo, int32_t hi, double scale)
{
	struct sh2000_status st;
	char why[400];
	int r;

	/* a stale heartbeat still fills st with the card's last word; the
	 * command that follows says what is wrong with the card */
	r = sh2000_poll_locked(h, &st);
	if (r < 0 && r != -SH2000_EHEARTBEAT)
		return r;
	r = judge(&st, (unsigned int)axis, lo, hi, scale, why, sizeof(why));
	return r ? sh2000_fail(h, r, "axis %c %s: %s", sh2000_axis_letter(axis),
			       what, why) : 0;
}
