/* SPDX-License-Identifier: MIT */
/*
 * The card's parameters in user units: names and units, validation
 * against the protocol's table (sh2000_param_lookup()) before anything is
 * written (the soft limits' position rule: softlimits.c), the conversion
 * to the card's words, get and set one at a time or an axis' whole set all
 * or none. Each goes to the card as a command (command.c).
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sh2000_internal.h"

static const char *const units[SH2000_GP_END] = {
	[SH2000_P_SCALE] = "counts/mm",
	[SH2000_P_KP] = "DAC/count",
	[SH2000_P_TI] = "s",
	[SH2000_P_TD] = "s",
	[SH2000_P_KVFF] = "DAC/(count/s)",
	[SH2000_P_KAFF] = "DAC/(count/s^2)",
	[SH2000_P_DAC_RANGE] = "",
	[SH2000_P_DAC_LIMIT] = "DAC codes",
	[SH2000_P_FERR_LIMIT] = "mm",
	[SH2000_P_SOFT_MIN] = "mm",
	[SH2000_P_SOFT_MAX] = "mm",
	[SH2000_P_VMAX] = "mm/s",
	[SH2000_P_AMAX] = "mm/s^2",
	[SH2000_P_HOME_VEL] = "mm/s",
	[SH2000_P_HOME_DEBOUNCE] = "servo cycles",
	[SH2000_P_HOME_OFFSET] = "mm",
	[SH2000_GP_COARSE_PERIOD_US] = "us",
	[SH2000_GP_FINE_STEPS] = "servo cycles",
	[SH2000_GP_HOST_TIMEOUT_MS] = "ms",
	[SH2000_GP_STATUS_PERIOD] = "servo cycles",
	[SH2000_GP_TIME_SCALE] = "1/10000 of full rate",
	[SH2000_GP_TIME_RAMP_MS] = "ms",
	[SH2000_GP_GANTRY_PAIR] = "axis mask",
	[SH2000_GP_GANTRY_KP] = "DAC/count",
	[SH2000_GP_GANTRY_TI] = "s",
	[SH2000_GP_GANTRY_TD] = "s",
	[SH2000_GP_GANTRY_SKEW_LIMIT] = "counts",
	[SH2000_GP_GANTRY_SQUARE] = "counts",
};

/* Parameters the library scales from mm to counts (x counts/mm). */
static int scaled(unsigned int id)
{
	switch (id) {
	case SH2000_P_FERR_LIMIT:
	case SH2000_P_SOFT_MIN:
	case SH2000_P_SOFT_MAX:
	case SH2000_P_VMAX:
	case SH2000_P_AMAX:
	case SH2000_P_HOME_VEL:
	case SH2000_P_HOME_OFFSET:
		return 1;
	default:
		return 0;
	}
}

static int is_global(unsigned int id)
{
	return id >= SH2000_GP_FIRST && id < SH2000_GP_END;
}

const char *sh2000_param_name(unsigned int id)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	return p ? p->name : NULL;
}

const char *sh2000_param_unit(unsigned int id)
{
	return id < SH2000_GP_END && sh2000_param_lookup(id) ? units[id] : NULL;
}

int sh2000_param_id(const char *name)
{
	unsigned int id;

	for (id = 0; name && id < SH2000_GP_END; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (p && p->name && !strcmp(p->name, name))
			return (int)id;
	}
	return -SH2000_EPARAM;
}

static void where(char *buf, size_t len, int axis, const char *name)
{
	if (axis == SH2000_GLOBAL)
		snprintf(buf, len, "global parameter %s", name);
	else
		snprintf(buf, len, "axis %c parameter %s",
			 sh2000_axis_letter(axis), name);
}

static const struct sh2000_param_info *check_id(struct sh2000 *h, int axis,
						unsigned int id, int *r)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);

	*r = 0;
	if (!p) {
		*r = sh2000_fail(h, -SH2000_EPARAM, "parameter %u: unknown", id);
	} else if (is_global(id) ? axis != SH2000_GLOBAL :
		   (axis < 0 || axis >= (int)SH2000_AXES)) {
		*r = sh2000_fail(h, -SH2000_EPARAM,
				 "parameter %s: %s", p->name,
				 is_global(id) ? "a global parameter: no axis" :
				 "needs an axis 0..3");
	} else {
		/* an older card would answer "unknown parameter": say why,
		 * as every feature of a later minor is refused */
		char what[64];

		snprintf(what, sizeof(what), "parameter %s needs", p->name);
		*r = sh2000_need_minor(h, sh2000_param_since_minor(id), what);
	}
	return *r ? NULL : p;
}

/* The one rule for a value, every front end's reason (sh2000.h). */
int sh2000_param_value_check(unsigned int id, double v, double scale,
			     double *card, char *why, size_t len)
{
	const struct sh2000_param_info *p = sh2000_param_lookup(id);
	double k = p && scaled(id) ? scale : 1.0;
	double c = v * k;
	const char *u = p ? units[id] : "";

	if (!p)
		return sh2000_msg(why, len, -SH2000_EPARAM, "parameter %u: unknown", id);
	if (!isfinite(v))
		return sh2000_msg(why, len, -SH2000_EPARAM, "%g is not a finite number", v);
	if (p->type == SH2000_PT_F32) {
		/* too small for a normal binary32 is refused like too large:
		 * never rounded to 0 */
		if (!isfinite(c) || fabs(c) > FLT_MAX ||
		    (c != 0.0 && fabs(c) < FLT_MIN))
			return sh2000_msg(why, len, -SH2000_EPARAM,
					  "%g %s does not fit a 32-bit float in card units",
					  v, u);
		c = sh2000_f32_value(sh2000_f32_bits(c));
	} else {
		double rc = nearbyint(c);

		if (!scaled(id) && rc != c)
			return sh2000_msg(why, len, -SH2000_EPARAM,
					  "%g is not an integer", v);
		if (!isfinite(rc) || rc < INT32_MIN || rc > INT32_MAX)
			return sh2000_msg(why, len, -SH2000_EPARAM,
					  "%g %s is %g counts: does not fit the card's 32-bit value",
					  v, u, rc);
		c = rc;
	}
	if (sh2000_param_in_range(p, c) != 0) {
		if (c >= p->min && c <= p->max &&
		    !(p->min_exclusive && c == p->min))
			return sh2000_msg(why, len, -SH2000_EPARAM,
					  "%g %s is not representable on the card (%s)",
					  v, u, p->type == SH2000_PT_F32 ?
					  "not a normal 32-bit float" :
					  id == SH2000_P_HOME_VEL ? "must not be 0" :
					  id == SH2000_GP_GANTRY_PAIR ?
					  "0 or the mask of two axes" :
					  "not an integer");
		return sh2000_msg(why, len, -SH2000_EPARAM,
				  "%g %s is outside %s%g..%g %s", v, u,
				  p->min_exclusive ? "(exclusive) " : "",
				  p->min / k, p->max / k, u);
	}
	if (card)
		*card = c;
	return 0;
}

/*
 * User value -> the 32-bit word the card gets, or -SH2000_EPARAM with a
 * message naming axis, parameter and the reason sh2000_param_value_check()
 * gives (the one every front end prints). Only reads h (for the message).
 */
static int encode(struct sh2000 *h, int axis, const struct sh2000_param_info *p,
		  double v, double scale, int32_t *word)
{
	char at[64], why[200];
	double c;
	int r;

	r = sh2000_param_value_check(p->id, v, scale, &c, why, sizeof(why));
	if (r < 0) {
		where(at, sizeof(at), axis, p->name);
		return sh2000_fail(h, r, "%s: %s", at, why);
	}
	*word = p->type == SH2000_PT_F32 ? (int32_t)sh2000_f32_bits(c) :
					   (int32_t)c;
	return 0;
}

static double decode_word(const struct sh2000_param_info *p, int32_t word,
			  double scale)
{
	double c;

	if (p->type == SH2000_PT_F32)
		c = sh2000_f32_value((uint32_t)word);
	else
		c = word;
	return scaled(p->id) ? c / scale : c;
}

int sh2000_param_check(struct sh2000 *h, int axis, unsigned int id,
		       double v, int32_t *word)
{
	const struct sh2000_param_info *p;
	int r;

	p = check_id(h, axis, id, &r);
	if (p)
		r = encode(h, axis, p, v, is_global(id) ? 1.0 : h->scale[axis],
			   word);
	return r;
}

static int get_locked(struct sh2000 *h, int axis, unsigned int id,
		      int32_t *word)
{
	return sh2000_command_locked(h, SH2000_CMD_GET_PARAM,
				     axis == SH2000_GLOBAL ? SH2000_AXIS_GLOBAL :
				     (unsigned int)axis, id, 0, word,
				     SH2000_CMD_TIMEOUT_MS);
}

static int set_locked(struct sh2000 *h, int axis, unsigned int id,
		      int32_t word)
{
	return sh2000_command_locked(h, SH2000_CMD_SET_PARAM,
				     axis == SH2000_GLOBAL ? SH2000_AXIS_GLOBAL :
				     (unsigned int)axis, id, word, NULL,
				     SH2000_CMD_TIMEOUT_MS);
}

int sh2000_global_get_locked(struct sh2000 *h, unsigned int id, int32_t *word)
{
	return get_locked(h, SH2000_GLOBAL, id, word);
}

int sh2000_global_set_locked(struct sh2000 *h, unsigned int id, int32_t word)
{
	int r = set_locked(h, SH2000_GLOBAL, id, word);

	if (!r && id == SH2000_GP_COARSE_PERIOD_US)
		h->coarse_us = word;
	if (!r && id == SH2000_GP_FINE_STEPS)
		h->fine_steps = word;
	if (!r && (id == SH2000_GP_COARSE_PERIOD_US ||
		   id == SH2000_GP_FINE_STEPS))
		sh2000_timing_changed(h);
	return r;
}

int sh2000_param_set(struct sh2000 *h, int axis, unsigned int id, double v)
{
	const struct sh2000_param_info *p;
	int32_t word = 0, other = 0;	/* set by encode() and get_locked() */
	double scale;
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_param_check(h, axis, id, v, &word);
	if (r)
		goto out;
	p = sh2000_param_lookup(id);
	scale = is_global(id) ? 1.0 : h->scale[axis];
	if (id == SH2000_P_SOFT_MIN || id == SH2000_P_SOFT_MAX) {
		unsigned int oid = id == SH2000_P_SOFT_MIN ? SH2000_P_SOFT_MAX :
				   SH2000_P_SOFT_MIN;

		r = get_locked(h, axis, oid, &other);
		if (r)
			goto out;
		if (id == SH2000_P_SOFT_MIN ? word >= other : word <= other) {
			r = sh2000_fail(h, -SH2000_EPARAM,
					"axis %c parameter %s: %g mm is not %s soft_%s (%g mm)",
					sh2000_axis_letter(axis), p->name, v,
					id == SH2000_P_SOFT_MIN ? "below" : "above",
					id == SH2000_P_SOFT_MIN ? "max" : "min",
					other / scale);
			goto out;
		}
		/* a scale alone keeps the card's counts: only new limits
		 * can leave the axis outside */
		r = id == SH2000_P_SOFT_MIN ?
		    sh2000_soft_limits_locked(h, axis, "parameter soft_min", word, other, scale) :
		    sh2000_soft_limits_locked(h, axis, "parameter soft_max", other, word, scale);
		if (r)
			goto out;
	}
	if (is_global(id)) {
		r = sh2000_global_set_locked(h, id, word);
	} else {
		r = set_locked(h, axis, id, word);
		if (!r && id == SH2000_P_SCALE)
			h->scale[axis] = v;
	}
out:
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_param_get(struct sh2000 *h, int axis, unsigned int id, double *v)
{
	const struct sh2000_param_info *p;
	int32_t word;
	int r;

	pthread_mutex_lock(&h->lock);
	p = check_id(h, axis, id, &r);
	if (p)
		r = get_locked(h, axis, id, &word);
	if (p && !r) {
		*v = decode_word(p, word, is_global(id) ? 1.0 : h->scale[axis]);
		if (id == SH2000_P_SCALE && *v > 0)
			h->scale[axis] = *v;
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}

void sh2000_axis_params_default(struct sh2000_axis_params *ap)
{
	const struct sh2000_param_info *ps = sh2000_param_lookup(SH2000_P_SCALE);
	double scale = ps && ps->def > 0 ? ps->def : 1.0;
	unsigned int id;

	for (id = 0; id < SH2000_AXIS_PARAMS; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		ap->v[id] = p ? (scaled(id) ? p->def / scale : p->def) : 0.0;
	}
}

int sh2000_axis_params_get(struct sh2000 *h, unsigned int axis,
			   struct sh2000_axis_params *ap)
{
	unsigned int id;
	int r = 0;

	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "no axis %u", axis);
	/* scale first: the rest is converted with it */
	r = sh2000_param_get(h, (int)axis, SH2000_P_SCALE, &ap->v[SH2000_P_SCALE]);
	for (id = 1; !r && id < SH2000_AXIS_PARAMS; id++)
		r = sh2000_param_get(h, (int)axis, id, &ap->v[id]);
	return r;
}

int sh2000_axis_params_set(struct sh2000 *h, unsigned int axis,
			   const struct sh2000_axis_params *ap)
{
	int32_t word[SH2000_AXIS_PARAMS];
	double scale = ap->v[SH2000_P_SCALE];
	unsigned int id;
	int r = 0;

	if (axis >= SH2000_AXES)
		return sh2000_fail(h, -EINVAL, "no axis %u", axis);
	pthread_mutex_lock(&h->lock);
	/* validate everything first, in the new scale; send only then */
	for (id = 0; !r && id < SH2000_AXIS_PARAMS; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);

		if (!p) {
			r = sh2000_fail(h, -SH2000_EPARAM, "parameter %u: unknown", id);
			break;
		}
		r = encode(h, (int)axis, p, ap->v[id], scale, &word[id]);
	}
	if (!r && word[SH2000_P_SOFT_MIN] >= word[SH2000_P_SOFT_MAX])
		r = sh2000_fail(h, -SH2000_EPARAM,
				"axis %c parameters soft_min %g mm and soft_max %g mm: out of order",
				sh2000_axis_letter((int)axis), ap->v[SH2000_P_SOFT_MIN],
				ap->v[SH2000_P_SOFT_MAX]);
	if (!r)
		r = sh2000_soft_limits_locked(h, (int)axis, "parameters",
					      word[SH2000_P_SOFT_MIN],
					      word[SH2000_P_SOFT_MAX], scale);
	if (!r) {
		/* The card keeps soft_min < soft_max after every single set:
		 * moving the window up sends max first, else min first. */
		int32_t cur_max = 0;
		unsigned int order[SH2000_AXIS_PARAMS], n = 0;

		r = get_locked(h, (int)axis, SH2000_P_SOFT_MAX, &cur_max);
		for (id = 0; id < SH2000_AXIS_PARAMS; id++)
			if (id != SH2000_P_SOFT_MIN && id != SH2000_P_SOFT_MAX)
				order[n++] = id;
		if (word[SH2000_P_SOFT_MIN] < cur_max) {
			order[n++] = SH2000_P_SOFT_MIN;
			order[n++] = SH2000_P_SOFT_MAX;
		} else {
			order[n++] = SH2000_P_SOFT_MAX;
			order[n++] = SH2000_P_SOFT_MIN;
		}
		for (id = 0; !r && id < n; id++) {
			r = set_locked(h, (int)axis, order[id], word[order[id]]);
			if (!r && order[id] == SH2000_P_SCALE)
				h->scale[axis] = scale;
		}
	}
	pthread_mutex_unlock(&h->lock);
	return r;
}
