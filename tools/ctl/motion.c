/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl enable, disable, jog, move, home, stop, estop, reset. Jog and
 * move plan a point-to-point motion with the library's planner within the
 * axes' vmax, amax and soft limits (as the card holds them) and stream it
 * with the segment push, in batches, ending with SH2000_PUSH_END.
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>

#include "ctl.h"

/* ---- enable / disable / stop / estop / reset ---------------------------- */

static int axes_args(int argc, char **argv, unsigned int *mask)
{
	*mask = 0;
	if (argc < 2)
		return sh2000_tool_usage(argv[0], "%s: which axes? (x y z a, x,y or all)",
					 argv[0]);
	for (int i = 1; i < argc; i++) {
		int m = sh2000_tool_axes(argv[i]);

		if (m < 0)
			return sh2000_tool_usage(argv[0],
				"%s: '%s' is not an axis list (x y z a, x,y, xyz or all)",
				argv[0], argv[i]);
		*mask |= (unsigned int)m;
	}
	return 0;
}

static int enable_disable(struct ctl *c, int argc, char **argv, int on)
{
	unsigned int mask;
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	r = axes_args(argc, argv, &mask);
	if (!r)
		r = ctl_open(c);
	if (r)
		return r;
	r = on ? sh2000_enable(c->h, mask) : sh2000_disable(c->h, mask);
	return r < 0 ? sh2000_tool_fail(c->h, r, argv[0]) : 0;
}

int ctl_enable(struct ctl *c, int argc, char **argv)
{
	return enable_disable(c, argc, argv, 1);
}

int ctl_disable(struct ctl *c, int argc, char **argv)
{
	return enable_disable(c, argc, argv, 0);
}

static int no_args(int argc, char **argv)
{
	if (argc > 1)
		return sh2000_tool_usage(argv[0], "%s: unexpected '%s'", argv[0],
					 argv[1]);
	return 0;
}

/* Poll until the card is neither RUNNING nor STOPPING (nor HOMING). */
static int wait_rest(struct ctl *c, double seconds)
{
	uint64_t end = sh2000_now_ns(c->h) + (uint64_t)(seconds * 1e9);
	struct sh2000_status st;
	int r;

	for (;;) {
		r = sh2000_poll(c->h, &st);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "status");
		if (st.card_state != SH2000_STATE_RUNNING &&
		    st.card_state != SH2000_STATE_STOPPING &&
		    st.card_state != SH2000_STATE_HOMING)
			return 0;
		if (sh2000_now_ns(c->h) > end) {
			sh2000_tool_msg("%s: still %s after %.1f s",
					sh2000_device(c->h),
					sh2000_state_name(st.card_state), seconds);
			return SH2000_EXIT_CARD;
		}
		sh2000_sleep_ns(c->h, 1000000);
	}
}

int ctl_stop(struct ctl *c, int argc, char **argv)
{
	int r, nowait = argc == 2 && !strcmp(argv[1], "--no-wait");

	if (ctl_want_help(argc, argv))
		return 0;
	if (!nowait && (r = no_args(argc, argv)))
		return r;
	if ((r = ctl_open(c)))
		return r;
	r = sh2000_stop(c->h);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "stop");
	return nowait ? 0 : wait_rest(c, 10.0);
}

int ctl_estop(struct ctl *c, int argc, char **argv)
{
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	if ((r = no_args(argc, argv)) || (r = ctl_open(c)))
		return r;
	r = sh2000_estop(c->h, 100);
	return r < 0 ? sh2000_tool_fail(c->h, r, "estop") : 0;
}

int ctl_reset(struct ctl *c, int argc, char **argv)
{
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	if ((r = no_args(argc, argv)) || (r = ctl_open(c)))
		return r;
	r = sh2000_reset(c->h);
	return r < 0 ? sh2000_tool_fail(c->h, r, "reset") : 0;
}

/* ---- home ----------------------------------------------------------------- */

int ctl_home(struct ctl *c, int argc, char **argv)
{
	unsigned int flags = 0;
	double timeout = 120.0;
	int axis = -1, r;

	if (ctl_want_help(argc, argv))
		return 0;
	for (int i = 1; i < argc; i++) {
		const char *v;
		int k;

		if (!strcmp(argv[i], "--index")) {
			flags |= SH2000_HOME_F_INDEX;
			continue;
		}
		k = ctl_opt_value(argc, argv, &i, "--timeout", 't', &v);
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (k > 0) {
			if (sh2000_tool_double(v, &timeout) < 0 || timeout <= 0)
				return sh2000_tool_usage(argv[0],
					"home: --timeout: '%s' is not a positive number of seconds", v);
			continue;
		}
		if (ctl_is_option(argv[i]) || axis >= 0)
			return sh2000_tool_usage(argv[0], "home: unexpected '%s'", argv[i]);
		axis = sh2000_tool_axis(argv[i]);
		if (axis < 0)
			return sh2000_tool_usage(argv[0], "home: '%s' is not an axis (x y z a)",
						 argv[i]);
	}
	if (axis < 0)
		return sh2000_tool_usage(argv[0], "home: which axis? (x y z a)");
	if ((r = ctl_open(c)))
		return r;
	r = sh2000_home(c->h, (unsigned int)axis, flags);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "home");
	r = sh2000_wait_idle(c->h, (int)(timeout * 1000));
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "home");
	{
		struct sh2000_status st;

		r = sh2000_poll(c->h, &st);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "status");
		if (!(st.axis[axis].state & SH2000_AXIS_HOMED)) {
			sh2000_tool_msg("%s: axis %c: homing ended without HOMED",
					sh2000_device(c->h), sh2000_tool_axis_name((unsigned int)axis));
			return SH2000_EXIT_CARD;
		}
		printf("%c homed at %.6f mm\n", sh2000_tool_axis_name((unsigned int)axis),
		       st.axis[axis].pos_mm);
	}
	return 0;
}

/* ---- planned motion: jog and move --------------------------------------- */

#define BATCH 32

/* SIGINT/SIGTERM during jog and move: stop the card, not just the tool */
static volatile sig_atomic_t interrupted;

static void on_interrupt(int sig)
{
	(void)sig;
	interrupted = 1;
}

struct stream {
	struct sh2000 *h;
	double pts[BATCH][SH2000_AXES];
	unsigned int n;
	int err;		/* first library error */
	uint64_t points;
	/* The planner's B-spline compensation lets control points overshoot
	 * the end of a motion by about 1 um, and the card checks the soft
	 * limits on the control points. A target at the limit is legitimate,
	 * so the moving axes' points are clamped to the limits: the card's
	 * spline stays inside the hull of its control points, so the
	 * set-point never passes the limit, and the end point is exact. */
	unsigned int clamp_mask;
	double lo[SH2000_AXES], hi[SH2000_AXES];
};

static int flush(struct stream *s, unsigned int flags)
{
	int r;

	if (!s->n)
		return 0;
	r = sh2000_wait_space(s->h, s->n, 5000);
	if (r >= 0)
		r = sh2000_push_mm(s->h, (const double (*)[SH2000_AXES])s->pts, s->n,
				   flags);
	if (r < 0) {
		s->err = r;
		return r;
	}
	s->n = 0;
	return 0;
}

static int sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct stream *s = ctx;

	if (interrupted)
		return -EINTR;
	memcpy(s->pts[s->n], pt->mm, sizeof(s->pts[0]));
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (!(s->clamp_mask & (1u << a)))
			continue;
		if (s->pts[s->n][a] > s->hi[a])
			s->pts[s->n][a] = s->hi[a];
		if (s->pts[s->n][a] < s->lo[a])
			s->pts[s->n][a] = s->lo[a];
	}
	s->n++;
	s->points++;
	if (s->n == BATCH || (pt->flags & SH2000_PATH_F_END))
		return flush(s, (pt->flags & SH2000_PATH_F_END) ? SH2000_PUSH_END : 0);
	return 0;
}

struct motion_setup {
	struct sh2000_path_config cfg;
	double start[SH2000_AXES];
	double soft_min[SH2000_AXES], soft_max[SH2000_AXES];
	unsigned int enabled;
};

/* The planner's configuration from the card: timing, each axis' vmax and
 * amax, where each axis is (set-point if enabled, else the encoder). */
static int motion_setup(struct ctl *c, struct motion_setup *m)
{
	struct sh2000_status st;
	double cp, fs;
	int r;

	sh2000_path_config_default(&m->cfg);
	r = sh2000_poll(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	r = sh2000_status_error(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "cannot move");
	if (st.card_state != SH2000_STATE_IDLE) {
		sh2000_tool_msg("%s: card is %s, not idle: nothing moved",
				sh2000_device(c->h), sh2000_state_name(st.card_state));
		return SH2000_EXIT_CARD;
	}
	if ((r = sh2000_param_get(c->h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, &cp)) < 0 ||
	    (r = sh2000_param_get(c->h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, &fs)) < 0)
		return sh2000_tool_fail(c->h, r, "get parameter");
	m->cfg.period_s = cp * 1e-6;
	m->cfg.fine_steps = (unsigned int)fs;
	m->enabled = 0;
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_axis_status *ax = &st.axis[a];

		if ((r = sh2000_param_get(c->h, (int)a, SH2000_P_VMAX, &m->cfg.vmax[a])) < 0 ||
		    (r = sh2000_param_get(c->h, (int)a, SH2000_P_AMAX, &m->cfg.amax[a])) < 0 ||
		    (r = sh2000_param_get(c->h, (int)a, SH2000_P_SOFT_MIN, &m->soft_min[a])) < 0 ||
		    (r = sh2000_param_get(c->h, (int)a, SH2000_P_SOFT_MAX, &m->soft_max[a])) < 0)
			return sh2000_tool_fail(c->h, r, "get parameter");
		if (ax->state & SH2000_AXIS_ENABLED) {
			m->enabled |= 1u << a;
			m->start[a] = ax->cmd_mm;
		} else {
			m->start[a] = ax->pos_mm;
		}
		m->cfg.start[a] = m->start[a];
	}
	return 0;
}

static int check_axes(struct ctl *c, const struct motion_setup *m,
		      unsigned int mask, const double target[SH2000_AXES])
{
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (!(mask & (1u << a)))
			continue;
		if (!(m->enabled & (1u << a))) {
			sh2000_tool_msg("%s: axis %c is not enabled (sh2000ctl enable %c): nothing moved",
					sh2000_device(c->h), sh2000_tool_axis_name(a),
					sh2000_tool_axis_name(a));
			return SH2000_EXIT_CARD;
		}
		if (target[a] < m->soft_min[a] || target[a] > m->soft_max[a]) {
			sh2000_tool_msg("%s: axis %c: target %g mm is outside the soft limits %g..%g mm: nothing moved",
					sh2000_device(c->h), sh2000_tool_axis_name(a),
					target[a], m->soft_min[a], m->soft_max[a]);
			return SH2000_EXIT_CARD;
		}
	}
	return 0;
}

/* Plan with fn, stream, wait for the end, report where the axes are. */
static int run_motion(struct ctl *c, struct motion_setup *m, unsigned int mask,
		      int (*plan)(struct sh2000_path *, void *), void *arg)
{
	struct stream s = { .h = c->h, .clamp_mask = mask };
	struct sh2000_path *p;
	struct sh2000_path_stats ps;
	struct sh2000_status st;
	struct sigaction sa;
	double end[SH2000_AXES];
	char err[256] = "";
	uint64_t deadline;
	double secs;
	int r;

	memcpy(s.lo, m->soft_min, sizeof(s.lo));
	memcpy(s.hi, m->soft_max, sizeof(s.hi));
	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_interrupt;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	r = sh2000_path_create(&p, &m->cfg, sink, &s, err, sizeof(err));
	if (r < 0) {
		sh2000_tool_msg("%s: planner: %s", sh2000_device(c->h), err);
		return SH2000_EXIT_CARD;
	}
	r = plan(p, arg);
	if (r < 0) {
		sh2000_tool_msg("%s: planner: %s: nothing moved", sh2000_device(c->h),
				sh2000_path_error(p));
		sh2000_path_destroy(p);
		return SH2000_EXIT_CARD;
	}
	sh2000_path_end_position(p, end);
	r = sh2000_path_finish(p);
	if (r >= 0)
		r = flush(&s, SH2000_PUSH_END);
	sh2000_path_stats(p, &ps);
	sh2000_path_destroy(p);
	if (s.err < 0 && !interrupted)
		return sh2000_tool_fail(c->h, s.err, "motion");
	if (r < 0 && !interrupted) {
		sh2000_tool_msg("%s: planner: %s", sh2000_device(c->h), strerror(-r));
		return SH2000_EXIT_CARD;
	}
	secs = (double)(s.points + 4) * m->cfg.period_s + 5.0;
	deadline = sh2000_now_ns(c->h) + (uint64_t)(secs * 1e9);
	for (;;) {
		if (interrupted) {
			r = sh2000_stop(c->h);
			sh2000_tool_msg("%s: interrupted: %s", sh2000_device(c->h),
					r < 0 ? "stop failed" : "card stopped");
			wait_rest(c, 5.0);
			return SH2000_EXIT_CARD;
		}
		/* short waits, so that an interrupt is seen */
		r = sh2000_wait_idle(c->h, 100);
		if (r != -SH2000_ETIMEOUT || sh2000_now_ns(c->h) > deadline)
			break;
	}
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "motion");
	r = sh2000_poll(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (!(mask & (1u << a)))
			continue;
		/* a stop from elsewhere leaves the card idle short of the end */
		if (fabs(st.axis[a].cmd_mm - end[a]) > 0.001) {
			sh2000_tool_msg("%s: axis %c stopped at %.6f mm, short of %.6f mm (stopped by another host?)",
					sh2000_device(c->h), sh2000_tool_axis_name(a),
					st.axis[a].cmd_mm, end[a]);
			return SH2000_EXIT_CARD;
		}
	}
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		if (mask & (1u << a))
			printf("%c %.6f mm\n", sh2000_tool_axis_name(a),
			       st.axis[a].pos_mm);
	return 0;
}

struct move_arg {
	double target[SH2000_AXES];
	double speed;
};

static int plan_move(struct sh2000_path *p, void *arg)
{
	struct move_arg *m = arg;

	return sh2000_path_move_abs(p, m->target, m->speed);
}

struct jog_arg {
	unsigned int axis;
	double velocity, travel;
};

static int plan_jog(struct sh2000_path *p, void *arg)
{
	struct jog_arg *j = arg;

	return sh2000_path_jog(p, j->axis, j->velocity, j->travel);
}

int ctl_move(struct ctl *c, int argc, char **argv)
{
	struct motion_setup m;
	struct move_arg ma = { .speed = 0 };
	double want[SH2000_AXES];
	unsigned int mask = 0;
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	for (int i = 1; i < argc; i++) {
		const char *v;
		char *eq;
		int k, a;

		k = ctl_opt_value(argc, argv, &i, "--feed", 'f', &v);
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (k > 0) {
			if (sh2000_tool_double(v, &ma.speed) < 0 || ma.speed <= 0)
				return sh2000_tool_usage(argv[0],
					"move: --feed: '%s' is not a positive speed in mm/s", v);
			continue;
		}
		eq = strchr(argv[i], '=');
		if (ctl_is_option(argv[i]) || !eq || eq - argv[i] != 1)
			return sh2000_tool_usage(argv[0],
				"move: '%s': expected AXIS=POS (e.g. x=10.5)", argv[i]);
		{
			char n[2] = { argv[i][0], 0 };

			a = sh2000_tool_axis(n);
		}
		if (a < 0 || sh2000_tool_double(eq + 1, &want[a]) < 0)
			return sh2000_tool_usage(argv[0],
				"move: '%s': expected AXIS=POS with AXIS x y z a and POS in mm",
				argv[i]);
		if (mask & (1u << a))
			return sh2000_tool_usage(argv[0], "move: axis %c given twice",
						 sh2000_tool_axis_name((unsigned int)a));
		mask |= 1u << a;
	}
	if (!mask)
		return sh2000_tool_usage(argv[0], "move: no target (AXIS=POS...)");
	if ((r = ctl_open(c)) || (r = motion_setup(c, &m)))
		return r;
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		ma.target[a] = (mask & (1u << a)) ? want[a] : m.start[a];
	if ((r = check_axes(c, &m, mask, ma.target)))
		return r;
	return run_motion(c, &m, mask, plan_move, &ma);
}

int ctl_jog(struct ctl *c, int argc, char **argv)
{
	struct motion_setup m;
	const char *vel_s = NULL, *time_s = NULL, *speed_s = NULL, *dist_s = NULL;
	double vel = 0, t = 0, speed = 0, dist = 0, target[SH2000_AXES];
	int axis = -1, r;

	if (ctl_want_help(argc, argv))
		return 0;
	for (int i = 1; i < argc; i++) {
		int k;

		if ((k = ctl_opt_value(argc, argv, &i, "--velocity", 'v', &vel_s)) ||
		    (k = ctl_opt_value(argc, argv, &i, "--time", 't', &time_s)) ||
		    (k = ctl_opt_value(argc, argv, &i, "--speed", 's', &speed_s))) {
			if (k < 0)
				return SH2000_EXIT_USAGE;
			continue;
		}
		if (ctl_is_option(argv[i]))
			return sh2000_tool_usage(argv[0], "jog: unknown option '%s'", argv[i]);
		if (axis < 0) {
			axis = sh2000_tool_axis(argv[i]);
			if (axis < 0)
				return sh2000_tool_usage(argv[0],
					"jog: '%s' is not an axis (x y z a)", argv[i]);
		} else if (!dist_s) {
			dist_s = argv[i];
		} else {
			return sh2000_tool_usage(argv[0], "jog: unexpected '%s'", argv[i]);
		}
	}
	if (axis < 0)
		return sh2000_tool_usage(argv[0], "jog: which axis? (x y z a)");
	if (dist_s && (vel_s || time_s))
		return sh2000_tool_usage(argv[0],
			"jog: give a DISTANCE or --velocity and --time, not both");
	if (!dist_s && !(vel_s && time_s))
		return sh2000_tool_usage(argv[0],
			"jog: needs a DISTANCE in mm, or --velocity MM/S and --time SECONDS");
	if (dist_s && (sh2000_tool_double(dist_s, &dist) < 0 || dist == 0))
		return sh2000_tool_usage(argv[0],
			"jog: '%s' is not a non-zero distance in mm", dist_s);
	if (speed_s && (!dist_s || sh2000_tool_double(speed_s, &speed) < 0 || speed <= 0))
		return sh2000_tool_usage(argv[0],
			"jog: --speed needs a DISTANCE and a positive speed in mm/s");
	if (vel_s && (sh2000_tool_double(vel_s, &vel) < 0 || vel == 0))
		return sh2000_tool_usage(argv[0],
			"jog: --velocity: '%s' is not a non-zero velocity in mm/s", vel_s);
	if (time_s && (sh2000_tool_double(time_s, &t) < 0 || t <= 0 || t > 3600))
		return sh2000_tool_usage(argv[0],
			"jog: --time: '%s' is not a time in seconds (0..3600]", time_s);
	if ((r = ctl_open(c)) || (r = motion_setup(c, &m)))
		return r;
	memcpy(target, m.start, sizeof(target));
	if (dist_s) {
		struct move_arg ma;

		target[axis] += dist;
		if ((r = check_axes(c, &m, 1u << axis, target)))
			return r;
		memcpy(ma.target, target, sizeof(target));
		ma.speed = speed;
		return run_motion(c, &m, 1u << axis, plan_move, &ma);
	}
	{
		struct jog_arg ja = { .axis = (unsigned int)axis, .velocity = vel };

		/* the jog ends at the soft limit if it would run past it */
		ja.travel = fabs(vel) * t;
		target[axis] += vel > 0 ? ja.travel : -ja.travel;
		if (target[axis] > m.soft_max[axis])
			ja.travel = m.soft_max[axis] - m.start[axis];
		if (target[axis] < m.soft_min[axis])
			ja.travel = m.start[axis] - m.soft_min[axis];
		if (ja.travel <= 0) {
			sh2000_tool_msg("%s: axis %c is at its soft limit: nothing moved",
					sh2000_device(c->h), sh2000_tool_axis_name((unsigned int)axis));
			return SH2000_EXIT_CARD;
		}
		if ((r = check_axes(c, &m, 1u << axis, m.start)))
			return r;
		return run_motion(c, &m, 1u << axis, plan_jog, &ja);
	}
}
