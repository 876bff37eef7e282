/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl index: arm an axis' index latch while the card runs or idles
 * (protocol 1.6), and wait for what it latched. The card's own homing on
 * the index is `home AXIS --index` (motion.c); this is the latch alone,
 * as a host that homes the axis itself (LinuxCNC through hal_sh2000) uses
 * it. Results are worded as home's ("x index at ... mm").
 */
#include <errno.h>
#include <string.h>

#include "ctl.h"

struct index_opts {
	int axis, wait;
	unsigned int flags;
	double within_mm, timeout_s;
};

static int parse(int argc, char **argv, struct index_opts *o)
{
	static const struct { const char *name; unsigned int flag; } fl[] = {
		{ "--mask", SH2000_INDEX_F_MASK },
		{ "--mask-invert", SH2000_INDEX_F_MASK | SH2000_INDEX_F_MASK_INVERT },
		{ "--invert", SH2000_INDEX_F_RISING },
	};

	for (int i = 1; i < argc; i++) {
		const char *v;
		int k, done = 0;

		for (size_t f = 0; f < sizeof(fl) / sizeof(fl[0]); f++)
			if (!strcmp(argv[i], fl[f].name)) {
				o->flags |= fl[f].flag;
				done = 1;
			}
		if (!strcmp(argv[i], "--wait"))
			o->wait = done = 1;
		if (done)
			continue;
		if ((k = ctl_opt_value(argc, argv, &i, "--within", 0, &v)) > 0) {
			if (sh2000_tool_double(v, &o->within_mm) < 0 || o->within_mm <= 0)
				return sh2000_tool_usage(argv[0],
					"index: --within: '%s' is not a positive distance in mm", v);
			continue;
		}
		if (k == 0 && (k = ctl_opt_value(argc, argv, &i, "--timeout", 't', &v)) > 0) {
			if (sh2000_tool_double(v, &o->timeout_s) < 0 || o->timeout_s <= 0)
				return sh2000_tool_usage(argv[0],
					"index: --timeout: '%s' is not a positive number of seconds", v);
			continue;
		}
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (ctl_is_option(argv[i]) || o->axis >= 0)
			return sh2000_tool_usage(argv[0], "index: unexpected '%s'", argv[i]);
		o->axis = sh2000_tool_axis(argv[i]);
		if (o->axis < 0)
			return sh2000_tool_usage(argv[0], "index: '%s' is not an axis (x y z a)",
						 argv[i]);
	}
	if (o->axis < 0)
		return sh2000_tool_usage(argv[0], "index: which axis? (x y z a)");
	return 0;
}

/* Until the axis' arm has ended (INDEX_ARMED gone), then its result. */
static int wait_result(struct ctl *c, const struct index_opts *o)
{
	struct sh2000_status st;
	struct sh2000_index ix;
	uint64_t end = sh2000_now_ns(c->h) + (uint64_t)(o->timeout_s * 1e9);
	char name = sh2000_tool_axis_name((unsigned int)o->axis);
	int r;

	for (;;) {
		r = sh2000_poll(c->h, &st);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "status");
		if (!(st.axis[o->axis].state & SH2000_AXIS_INDEX_ARMED))
			break;
		if (sh2000_now_ns(c->h) >= end) {
			sh2000_tool_msg("%c: no index mark in %g s (still armed)", name,
					o->timeout_s);
			return SH2000_EXIT_CARD;
		}
		sh2000_sleep_ns(c->h, 1000000);
	}
	while ((r = sh2000_index_read(c->h, (unsigned int)o->axis, &st, &ix)) == -EAGAIN)
		sh2000_sleep_ns(c->h, 100000);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "index");
	switch (ix.state) {
	case SH2000_INDEX_LATCHED:
		printf("%c index at %.6f mm (cycle %llu)\n", name, ix.mm,
		       (unsigned long long)ix.cycle);
		return 0;
	case SH2000_INDEX_MISSED:
		sh2000_tool_msg("%c: no index mark within the arm's travel", name);
		break;
	case SH2000_INDEX_ABORTED:
		sh2000_tool_msg("%c: the index arm ended without a mark (axis disabled, fault or emergency stop)",
				name);
		break;
	default:
		sh2000_tool_msg("%c: the index latch is not armed", name);
	}
	return SH2000_EXIT_CARD;
}

int ctl_index(struct ctl *c, int argc, char **argv)
{
	struct index_opts o = { .axis = -1, .timeout_s = 120.0 };
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	if ((r = parse(argc, argv, &o)) || (r = ctl_open(c)))
		return r;
	/* --wait alone waits for the arm made before; anything else arms */
	if (!o.wait || o.flags || o.within_mm > 0) {
		r = sh2000_index_arm(c->h, (unsigned int)o.axis, o.flags, o.within_mm);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "index");
		if (!o.wait) {
			printf("%c index armed (arm %d)\n",
			       sh2000_tool_axis_name((unsigned int)o.axis), r);
			return 0;
		}
	}
	return wait_result(c, &o);
}
