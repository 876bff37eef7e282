// SPDX-License-Identifier: MIT
/*
 * sh2000ctl status: the gantry pair (protocol 1.7), when the card has one:
 * its axes, the coupling loop's gains, the skew limit and squaring, and
 * the skew now, from the status snapshot's set-points and positions (the
 * difference of the two sides' following errors, as the card computes
 * it). And whether the card has a parameter at all (older protocols).
 */
#include <json-c/json.h>
#include <stdio.h>

#include "ctl.h"

int ctl_card_has(struct ctl *c, unsigned int id)
{
	return SH2000_PROTO_VERSION_MINOR(sh2000_card_version(c->h)) >=
	       sh2000_param_since_minor(id);
}

int ctl_pair_get(struct ctl *c, const struct sh2000_status *st,
		 struct ctl_pair *p)
{
	static const unsigned int ids[] = {
		SH2000_GP_GANTRY_PAIR, SH2000_GP_GANTRY_KP, SH2000_GP_GANTRY_TI,
		SH2000_GP_GANTRY_TD, SH2000_GP_GANTRY_SKEW_LIMIT,
		SH2000_GP_GANTRY_SQUARE,
	};
	double v[6];
	unsigned int i, n = 0;

	p->on = 0;
	if (!ctl_card_has(c, SH2000_GP_GANTRY_PAIR))
		return 0;
	for (i = 0; i < 6; i++) {
		int r = sh2000_param_get(c->h, SH2000_GLOBAL, ids[i], &v[i]);

		if (r < 0)
			return sh2000_tool_fail(c->h, r, "get parameter");
	}
	for (i = 0; i < SH2000_AXES; i++) {
		if (!((unsigned int)v[0] & (1u << i)))
			continue;
		if (n < 2)
			p->axis[n] = i;
		n++;
	}
	if (n != 2)
		return 0;
	p->on = 1;
	p->kp = v[1];
	p->ti = v[2];
	p->td = v[3];
	p->limit_counts = (long long)v[4];
	p->square_counts = (long long)v[5];
	p->skew_counts = st->axis[p->axis[0]].ferr_counts -
			 st->axis[p->axis[1]].ferr_counts;
	p->skew_mm = st->axis[p->axis[0]].ferr_mm - st->axis[p->axis[1]].ferr_mm;
	p->fault = ((st->axis[p->axis[0]].faults | st->axis[p->axis[1]].faults) &
		    SH2000_AXIS_FAULT_SKEW) != 0;
	return 0;
}

void ctl_pair_print(const struct ctl_pair *p)
{
	if (!p->on)
		return;
	printf("gantry %c+%c: skew %lld counts (%.6f mm), limit %lld counts%s; "
	       "coupling kp %g ti %g td %g; square %lld counts\n",
	       sh2000_tool_axis_name(p->axis[0]), sh2000_tool_axis_name(p->axis[1]),
	       p->skew_counts, p->skew_mm, p->limit_counts,
	       p->fault ? " (SKEW fault latched)" : "", p->kp, p->ti, p->td,
	       p->square_counts);
}

struct json_object *ctl_pair_json(const struct ctl_pair *p)
{
	json_object *o, *ax;
	char n[2] = { 0, 0 };

	if (!p->on)
		return NULL;
	o = json_object_new_object();
	ax = json_object_new_array();
	for (unsigned int i = 0; i < 2; i++) {
		n[0] = sh2000_tool_axis_name(p->axis[i]);
		json_object_array_add(ax, json_object_new_string(n));
	}
	json_object_object_add(o, "axes", ax);
	json_object_object_add(o, "skew_counts", json_object_new_int64(p->skew_counts));
	json_object_object_add(o, "skew_mm", json_object_new_double(p->skew_mm));
	json_object_object_add(o, "skew_limit_counts",
			       json_object_new_int64(p->limit_counts));
	json_object_object_add(o, "skew_fault", json_object_new_boolean(p->fault));
	json_object_object_add(o, "kp", json_object_new_double(p->kp));
	json_object_object_add(o, "ti", json_object_new_double(p->ti));
	json_object_object_add(o, "td", json_object_new_double(p->td));
	json_object_object_add(o, "square_counts",
			       json_object_new_int64(p->square_counts));
	return o;
}
