/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl enable, disable, jog, move, home, stop, estop, reset. Jog and
 * move plan a point-to-point motion and run it through libsh2000-motion's
 * runner (sh2000/run.h), the same streaming path as sh2000-upload: the
 * axes' vmax, amax and soft limits as the card holds them, the one
 * soft-limit policy, and a STOP from another program ends the motion the
 * same way (exit 7, nothing latched).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sh2000/path.h>
#include <sh2000/run.h>

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
	if (r >= 0 && !nowait)
		r = sh2000_wait_rest(c->h, 10000);
	return r < 0 ? sh2000_tool_fail(c->h, r, "stop") : 0;
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

/* An axis a command needs is not enabled: the hint says how to enable it. */
static int not_enabled(struct ctl *c, unsigned int a)
{
	char an = sh2000_tool_axis_name(a);

	/* the in-process card is new in every program: a separate
	 * `sh2000ctl enable` enables another card */
	if (sh2000_backend(c->h) == SH2000_BACKEND_SIM)
		sh2000_tool_msg("%s: axis %c is not enabled (the in-process card is new in every program: sh2000ctl -d sim enable %c + ...): nothing moved",
				sh2000_device(c->h), an, an);
	else
		sh2000_tool_msg("%s: axis %c is not enabled (sh2000ctl enable %c): nothing moved",
				sh2000_device(c->h), an, an);
	return SH2000_EXIT_CARD;
}

static int home_args(int argc, char **argv, int *axis, unsigned int *flags,
		     double *timeout)
{
	for (int i = 1; i < argc; i++) {
		const char *v;
		int k;

		if (!strcmp(argv[i], "--index")) {
			*flags |= SH2000_HOME_F_INDEX;
			continue;
		}
		k = ctl_opt_value(argc, argv, &i, "--timeout", 't', &v);
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (k > 0) {
			if (sh2000_tool_double(v, timeout) < 0 || *timeout <= 0)
				return sh2000_tool_usage(argv[0],
					"home: --timeout: '%s' is not a positive number of seconds", v);
			continue;
		}
		if (ctl_is_option(argv[i]) || *axis >= 0)
			return sh2000_tool_usage(argv[0], "home: unexpected '%s'", argv[i]);
		*axis = sh2000_tool_axis(argv[i]);
		if (*axis < 0)
			return sh2000_tool_usage(argv[0], "home: '%s' is not an axis (x y z a)",
						 argv[i]);
	}
	if (*axis < 0)
		return sh2000_tool_usage(argv[0], "home: which axis? (x y z a)");
	return 0;
}

/* The stop check sh2000_run_home_until() asks: SIGINT or SIGTERM. */
static int stop_asked(void *ctx)
{
	(void)ctx;
	return sh2000_tool_stop_asked();
}

/* How the homing ended, in the operator's words and exit codes: "homed
 * at" with the set-point (where the card holds the axis, 0 at the home
 * point) and, apart, the encoder and following error the loop still
 * settles out; the library's words otherwise. */
static int home_report(struct ctl *c, unsigned int axis, double timeout,
		       int r, const char *msg)
{
	struct sh2000_status st;

	if (r == -SH2000_ECMD_DISABLED && sh2000_poll(c->h, &st) == 0 &&
	    !(st.axis[axis].state & SH2000_AXIS_ENABLED))
		return not_enabled(c, axis);
	if (r == -ECANCELED || r == -SH2000_ESTOPPED) {
		sh2000_tool_msg("%s", msg);
		return SH2000_EXIT_STOPPED;
	}
	if (r == -SH2000_ETIMEOUT) {
		sh2000_tool_msg("%s: home: not homed after %g s (--timeout): homing stopped, card at rest",
				sh2000_device(c->h), timeout);
		return SH2000_EXIT_CARD;
	}
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "home");
	r = sh2000_poll(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	printf("%c homed at %.6f mm (set-point; encoder %.6f mm, following error %.6f mm)\n",
	       sh2000_tool_axis_name(axis), st.axis[axis].cmd_mm,
	       st.axis[axis].pos_mm, st.axis[axis].ferr_mm);
	return 0;
}

int ctl_home(struct ctl *c, int argc, char **argv)
{
	unsigned int flags = 0;
	double timeout = 120.0;
	char msg[256];
	int axis = -1, r;

	if (ctl_want_help(argc, argv))
		return 0;
	if ((r = home_args(argc, argv, &axis, &flags, &timeout)) || (r = ctl_open(c)))
		return r;
	/* SIGINT/SIGTERM while the card homes: stop it, as jog and move do */
	sh2000_tool_catch_stop(SH2000_SECOND_COUNTS);
	r = sh2000_run_home_until(c->h, (unsigned int)axis, flags,
				  (int)(timeout * 1e3), stop_asked, NULL,
				  msg, sizeof(msg));
	return home_report(c, (unsigned int)axis, timeout, r, msg);
}

/* ---- planned motion: jog and move --------------------------------------- */

struct motion_setup {
	struct sh2000_path_config cfg;
	struct sh2000_limits limits;
	double start[SH2000_AXES];
	unsigned int enabled;
};

/* The planner's configuration from the card (timing, each axis' vmax,
 * amax and scale, where each axis is) and its soft limits. */
static int motion_setup(struct ctl *c, struct motion_setup *m)
{
	struct sh2000_status st;
	int r;

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
	if ((r = sh2000_run_path_config(c->h, &m->cfg)) < 0 ||
	    (r = sh2000_limits_get(c->h, &m->limits)) < 0)
		return sh2000_tool_fail(c->h, r, "get parameter");
	m->enabled = 0;
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (st.axis[a].state & SH2000_AXIS_ENABLED)
			m->enabled |= 1u << a;
		m->start[a] = m->cfg.start[a];
	}
	return 0;
}

/*
 * An enabled axis whose set-point is outside its soft limits (new limits
 * set around it, or a card that powered up there) cannot move at all:
 * the card faults a set-point outside them, so the runner refuses the
 * very first point. Say so in the operator's terms, with the way back.
 */
static int check_start(struct ctl *c, const struct motion_setup *m)
{
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double lo = m->limits.lo[a], hi = m->limits.hi[a], at = m->start[a];
		char an = sh2000_tool_axis_name(a);

		if (!(m->enabled & (1u << a)) ||
		    (at >= lo - SH2000_LIMIT_SLACK_MM && at <= hi + SH2000_LIMIT_SLACK_MM))
			continue;
		sh2000_tool_msg("%s: axis %c is at %.4f mm, outside its soft limits %.4f..%.4f mm, and the card refuses any set-point outside them: nothing moved. To get back: widen them (sh2000ctl params %c soft_%s=%.4f), move %c inside, then set soft_%s=%.4f again",
				sh2000_device(c->h), an, at, lo, hi, an,
				at < lo ? "min" : "max", at < lo ? floor(at) : ceil(at),
				an, at < lo ? "min" : "max", at < lo ? lo : hi);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

static int check_axes(struct ctl *c, const struct motion_setup *m,
		      unsigned int mask, const double target[SH2000_AXES])
{
	double t[SH2000_AXES];
	char why[200];

	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (!(mask & (1u << a)) || (m->enabled & (1u << a)))
			continue;
		return not_enabled(c, a);
	}
	if (check_start(c, m))
		return SH2000_EXIT_CARD;
	/* the runner's rule, before anything moves */
	memcpy(t, target, sizeof(t));
	if (sh2000_limits_apply(&m->limits, t, why, sizeof(why)) < 0) {
		sh2000_tool_msg("%s: target: %s: nothing moved",
				sh2000_device(c->h), why);
		return SH2000_EXIT_CARD;
	}
	return 0;
}

/* The runner calls this after every batch and poll: where a signal
 * becomes a stop on the path. */
static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct sh2000_run **run = ctx;

	(void)p;
	if (sh2000_tool_stop_asked() && *run)
		sh2000_run_stop(*run);
}

/* How a run that did not end at its end point ended: an exit code. */
static int run_ended(struct ctl *c, struct sh2000_run *run, int r)
{
	if (sh2000_tool_stop_asked()) {
		sh2000_tool_msg("%s: interrupted: card stopped", sh2000_device(c->h));
		return SH2000_EXIT_STOPPED;
	}
	/* another program's STOP: one line says it (the runner's own words,
	 * "the card stopped the motion", would say it twice) */
	if (r == -SH2000_ESTOPPED) {
		sh2000_tool_msg("%s: stopped by another program (a STOP command); the card is at rest on the path",
				sh2000_device(c->h));
		return SH2000_EXIT_STOPPED;
	}
	sh2000_tool_msg("%s", sh2000_run_error(run));
	return r == -SH2000_ELIMIT ? SH2000_EXIT_CARD : sh2000_tool_exit_code(r);
}

/* Where the axes ended; exit 1 if the set-point is short of the end. */
static int report_end(struct ctl *c, unsigned int mask,
		      const double end[SH2000_AXES])
{
	struct sh2000_status st;
	int r = sh2000_poll(c->h, &st);

	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		if (!(mask & (1u << a)))
			continue;
		if (fabs(st.axis[a].cmd_mm - end[a]) > 0.001) {
			sh2000_tool_msg("%s: axis %c stopped at %.6f mm, short of %.6f mm",
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

/* Plan with fn and run it through the runner; report where the axes are. */
static int run_motion(struct ctl *c, struct motion_setup *m, unsigned int mask,
		      int (*plan)(struct sh2000_path *, void *), void *arg)
{
	struct sh2000_run_config rc;
	struct sh2000_run *run = NULL;
	double end[SH2000_AXES];
	char err[512] = "";
	int r;

	/* SIGINT/SIGTERM during jog and move: stop the card, not just the
	 * tool (on_progress) */
	sh2000_tool_catch_stop(SH2000_SECOND_COUNTS);
	sh2000_run_config_default(&rc);
	rc.progress = on_progress;
	rc.ctx = &run;		/* filled in by the create */
	r = sh2000_run_create(&run, c->h, &m->cfg, &rc, err, sizeof(err));
	if (r < 0) {
		sh2000_tool_msg("%s: nothing moved", err);
		return sh2000_tool_exit_code(r);
	}
	r = plan(sh2000_run_path(run), arg);
	if (r >= 0) {
		sh2000_path_end_position(sh2000_run_path(run), end);
		r = sh2000_run_finish(run);
	}
	if (r < 0 || sh2000_tool_stop_asked()) {
		r = run_ended(c, run, r);
		sh2000_run_destroy(run);
		return r;
	}
	sh2000_run_destroy(run);
	return report_end(c, mask, end);
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

		if ((r = check_axes(c, &m, 1u << axis, m.start)))
			return r;
		/* the jog ends at the soft limit if it would run past it */
		ja.travel = fabs(vel) * t;
		target[axis] += vel > 0 ? ja.travel : -ja.travel;
		if (target[axis] > m.limits.hi[axis])
			ja.travel = m.limits.hi[axis] - m.start[axis];
		if (target[axis] < m.limits.lo[axis])
			ja.travel = m.start[axis] - m.limits.lo[axis];
		if (ja.travel <= 0) {
			sh2000_tool_msg("%s: axis %c is at its soft limit: nothing moved",
					sh2000_device(c->h), sh2000_tool_axis_name((unsigned int)axis));
			return SH2000_EXIT_CARD;
		}
		return run_motion(c, &m, 1u << axis, plan_jog, &ja);
	}
}
