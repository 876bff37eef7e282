/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl params: get and set parameters in user units, from the command
 * line or a parameter file. Both go through one plan: collect every value,
 * check all of them against the protocol's ranges (in the scale they will
 * be converted with) and the card's cross rules, and only then send; so a
 * bad value or a bad file line sets nothing. The file format and its
 * reader are in params_plan.h.
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl.h"
#include "params_plan.h"

int ctl_param_is_mm(unsigned int id)
{
	const char *u = sh2000_param_unit(id);

	return u && !strncmp(u, "mm", 2);
}

static int plan_read_file(struct ctl_plan *p, const char *path)
{
	FILE *f = strcmp(path, "-") ? fopen(path, "r") : stdin;
	int r;

	p->file = strcmp(path, "-") ? path : "<stdin>";
	if (!f) {
		sh2000_tool_msg("%s: cannot open: %s", path, strerror(errno));
		return -1;
	}
	r = ctl_plan_read(p, f, path);
	if (f != stdin)
		fclose(f);
	return r;
}

/* Section s's current values from the card into cur[s]: 0 or an exit
 * code. */
static int read_section(struct ctl *c, unsigned int s,
			double cur[SH2000_AXES + 1][SH2000_GP_END])
{
	unsigned int lo = s == CTL_SECT_GLOBAL ? SH2000_GP_FIRST : 0;
	unsigned int hi = s == CTL_SECT_GLOBAL ? SH2000_GP_END : SH2000_AXIS_PARAMS;

	for (unsigned int id = lo; id < hi; id++) {
		int r;

		if (!sh2000_param_lookup(id) || !ctl_card_has(c, id)) {
			/* an older card: only a set names it (refused) */
			cur[s][id] = 0.0;
			continue;
		}
		r = sh2000_param_get(c->h, s == CTL_SECT_GLOBAL ? SH2000_GLOBAL : (int)s,
				     id, &cur[s][id]);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "get parameter");
	}
	return 0;
}

/* Section s's values as the card would hold them (card units: counts for
 * lengths) in card[]; bad[id] set for each value the library refuses
 * (its words printed). */
static void section_values(struct ctl_plan *p, unsigned int s, double scale,
			   double cur[SH2000_AXES + 1][SH2000_GP_END],
			   double card[SH2000_GP_END], int bad[SH2000_GP_END])
{
	unsigned int lo = s == CTL_SECT_GLOBAL ? SH2000_GP_FIRST : 0;
	unsigned int hi = s == CTL_SECT_GLOBAL ? SH2000_GP_END : SH2000_AXIS_PARAMS;
	char why[256];

	for (unsigned int id = lo; id < hi; id++) {
		const struct sh2000_param_info *pi = sh2000_param_lookup(id);

		bad[id] = 0;
		if (!pi)
			continue;
		if (!p->set[s][id]) {
			/* the card keeps counts: unchanged ones stay */
			double k = ctl_param_is_mm(id) ? cur[s][SH2000_P_SCALE] : 1.0;

			card[id] = nearbyint(cur[s][id] * k);
			if (pi->type == SH2000_PT_F32)
				card[id] = cur[s][id] * k;
			continue;
		}
		/* the library's rule and words, in card units */
		if (sh2000_param_value_check(id, p->v[s][id], scale, &card[id],
					     why, sizeof(why)) < 0) {
			bad[id] = 1;
			ctl_plan_error(p, p->line[s][id], "%s%s%s: %s",
				       s == CTL_SECT_GLOBAL ? "" : ctl_plan_section(s),
				       s == CTL_SECT_GLOBAL ? "" : " ", pi->name, why);
		}
	}
}

/* The later of two values' lines (where a cross rule is reported). */
static int later_line(const struct ctl_plan *p, unsigned int s,
		      unsigned int a, unsigned int b)
{
	return p->line[s][a] > p->line[s][b] ? p->line[s][a] : p->line[s][b];
}

/*
 * New soft limits (or a new scale with them) judged by the library's rule
 * (sh2000_soft_limits_check(): an enabled or homed axis must not be left
 * outside them), reported at the plan's line that set them.
 */
static void position_check(struct ctl_plan *p, unsigned int s,
			   const struct sh2000_status *st,
			   const double card[SH2000_GP_END], double scale)
{
	int line = later_line(p, s, SH2000_P_SOFT_MIN, SH2000_P_SOFT_MAX);
	char why[400];

	if (sh2000_soft_limits_check(st, s, card[SH2000_P_SOFT_MIN] / scale,
				     card[SH2000_P_SOFT_MAX] / scale, scale,
				     why, sizeof(why)) < 0)
		ctl_plan_error(p, line > 0 ? line : p->line[s][SH2000_P_SCALE],
			       "%s", why);
}

/* The rules across values of section s: soft_min below soft_max, the
 * position inside the soft limits, the timing. Each runs unless a value
 * it needs was refused already (every error of a file is printed). */
static void cross_check(struct ctl_plan *p, unsigned int s,
			const struct sh2000_status *st,
			const double card[SH2000_GP_END], const int bad[SH2000_GP_END],
			double scale)
{
	const int *set = p->set[s];

	if (s != CTL_SECT_GLOBAL && (set[SH2000_P_SOFT_MIN] || set[SH2000_P_SOFT_MAX] ||
				     set[SH2000_P_SCALE]) &&
	    !bad[SH2000_P_SOFT_MIN] && !bad[SH2000_P_SOFT_MAX] && !bad[SH2000_P_SCALE]) {
		if (card[SH2000_P_SOFT_MIN] >= card[SH2000_P_SOFT_MAX]) {
			if (set[SH2000_P_SOFT_MIN] || set[SH2000_P_SOFT_MAX])
				ctl_plan_error(p, later_line(p, s, SH2000_P_SOFT_MIN, SH2000_P_SOFT_MAX),
					       "%s soft_min %g mm must be below soft_max %g mm",
					       ctl_plan_section(s), card[SH2000_P_SOFT_MIN] / scale,
					       card[SH2000_P_SOFT_MAX] / scale);
		} else if (set[SH2000_P_SOFT_MIN] || set[SH2000_P_SOFT_MAX]) {
			position_check(p, s, st, card, scale);
		}
	}
	if (s == CTL_SECT_GLOBAL &&
	    (set[SH2000_GP_COARSE_PERIOD_US] || set[SH2000_GP_FINE_STEPS]) &&
	    !bad[SH2000_GP_COARSE_PERIOD_US] && !bad[SH2000_GP_FINE_STEPS]) {
		double cp = card[SH2000_GP_COARSE_PERIOD_US];
		double fs = card[SH2000_GP_FINE_STEPS];

		if (!sh2000_timing_ok((long long)cp, (long long)fs))
			ctl_plan_error(p, later_line(p, s, SH2000_GP_COARSE_PERIOD_US,
						     SH2000_GP_FINE_STEPS),
				       "coarse_period_us %g with fine_steps %g: the servo period must be a whole number of ns >= %u ns",
				       cp, fs, SH2000_FW_MIN_SERVO_NS);
	}
}

/* Check the plan against the card's current values; nothing is sent.
 * Every error is printed, the cross rules' too. */
static int plan_check(struct ctl *c, struct ctl_plan *p,
		      double cur[SH2000_AXES + 1][SH2000_GP_END])
{
	struct sh2000_status st;
	int r;

	p->dev = sh2000_device(c->h);
	r = sh2000_poll(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	for (unsigned int s = 0; s <= CTL_SECT_GLOBAL; s++) {
		double scale, card[SH2000_GP_END];
		int any = 0, bad[SH2000_GP_END];

		for (unsigned int id = 0; id < SH2000_GP_END; id++)
			any |= p->set[s][id];
		if (!any)
			continue;
		if ((r = read_section(c, s, cur)))
			return r;
		scale = p->set[s][SH2000_P_SCALE] && s != CTL_SECT_GLOBAL ?
			p->v[s][SH2000_P_SCALE] : cur[s][SH2000_P_SCALE];
		if (s == CTL_SECT_GLOBAL)
			scale = 1.0;
		section_values(p, s, scale, cur, card, bad);
		cross_check(p, s, &st, card, bad, scale);
	}
	return p->errors ? SH2000_EXIT_CARD : 0;
}

static int set_one(struct ctl *c, int axis, unsigned int id, double v)
{
	int r = sh2000_param_set(c->h, axis, id, v);

	return r < 0 ? sh2000_tool_fail(c->h, r, "set parameter") : 0;
}

/*
 * Whether axis a's new soft_min goes to the card before its soft_max. The
 * card takes one at a time and the library judges each window on the way
 * (in counts, as the card compares them; scale goes first, so the new min
 * is in the new scale, the current max in the old): min first when the
 * window new min..current max is in order and keeps the axis inside it
 * (sh2000_soft_limits_check()), else max first, which then is legal: the
 * new min is at or above the current max, or the axis above the current
 * max and (the plan was checked) inside the new window.
 */
static int limits_min_first(const struct ctl_plan *p, unsigned int a,
			    const struct sh2000_status *st,
			    double cur[SH2000_AXES + 1][SH2000_GP_END])
{
	double k, lo, hi;

	if (!p->set[a][SH2000_P_SOFT_MIN])
		return 1;
	k = p->set[a][SH2000_P_SCALE] ? p->v[a][SH2000_P_SCALE] : cur[a][SH2000_P_SCALE];
	lo = nearbyint(p->v[a][SH2000_P_SOFT_MIN] * k);
	hi = nearbyint(cur[a][SH2000_P_SOFT_MAX] * cur[a][SH2000_P_SCALE]);
	return lo < hi && !sh2000_soft_limits_check(st, a, lo / k, hi / k, k, NULL, 0);
}

/* Send a checked plan: globals, then each axis (scale first, the soft
 * limits in the order that keeps soft_min < soft_max on the card and the
 * axis inside them: limits_min_first()). */
static int plan_apply(struct ctl *c, struct ctl_plan *p,
		      double cur[SH2000_AXES + 1][SH2000_GP_END])
{
	struct sh2000_status st;
	int r;

	r = sh2000_poll(c->h, &st);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "status");
	if (sh2000_state_moving(st.card_state)) {
		const struct sh2000_param_info *fixed = NULL;
		char live[256];

		for (unsigned int s = 0; s <= CTL_SECT_GLOBAL; s++)
			for (unsigned int id = 0; id < SH2000_GP_END; id++)
				if (p->set[s][id] && !sh2000_param_lookup(id)->live)
					fixed = sh2000_param_lookup(id);
		if (fixed) {
			sh2000_tool_msg("%s: card is %s: %s cannot change while the card moves; only live parameters (%s) may change now; nothing set",
					sh2000_device(c->h), sh2000_state_name(st.card_state),
					fixed->name, sh2000_param_live_names(live, sizeof(live)));
			return SH2000_EXIT_CARD;
		}
	}
	if (p->set[CTL_SECT_GLOBAL][SH2000_GP_COARSE_PERIOD_US] ||
	    p->set[CTL_SECT_GLOBAL][SH2000_GP_FINE_STEPS]) {
		/* the library takes the card there through legal states */
		double *g = p->v[CTL_SECT_GLOBAL];
		int *set = p->set[CTL_SECT_GLOBAL];
		double tc = set[SH2000_GP_COARSE_PERIOD_US] ? g[SH2000_GP_COARSE_PERIOD_US] :
			    cur[CTL_SECT_GLOBAL][SH2000_GP_COARSE_PERIOD_US];
		double tf = set[SH2000_GP_FINE_STEPS] ? g[SH2000_GP_FINE_STEPS] :
			    cur[CTL_SECT_GLOBAL][SH2000_GP_FINE_STEPS];

		r = sh2000_set_timing(c->h, (unsigned int)tc, (unsigned int)tf);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "set the timing");
		set[SH2000_GP_COARSE_PERIOD_US] = set[SH2000_GP_FINE_STEPS] = 0;
	}
	for (unsigned int id = SH2000_GP_FIRST; id < SH2000_GP_END; id++)
		if (p->set[CTL_SECT_GLOBAL][id] &&
		    (r = set_one(c, SH2000_GLOBAL, id, p->v[CTL_SECT_GLOBAL][id])))
			return r;
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		unsigned int order[SH2000_AXIS_PARAMS], n = 0;
		int min_first;

		for (unsigned int id = 0; id < SH2000_AXIS_PARAMS; id++)
			if (id != SH2000_P_SOFT_MIN && id != SH2000_P_SOFT_MAX)
				order[n++] = id;
		min_first = limits_min_first(p, a, &st, cur);
		order[n++] = min_first ? SH2000_P_SOFT_MIN : SH2000_P_SOFT_MAX;
		order[n++] = min_first ? SH2000_P_SOFT_MAX : SH2000_P_SOFT_MIN;
		for (unsigned int k = 0; k < n; k++)
			if (p->set[a][order[k]] &&
			    (r = set_one(c, (int)a, order[k], p->v[a][order[k]])))
				return r;
	}
	return 0;
}

/*
 * After a new scale: the card keeps lengths in counts, so every length
 * the plan did not set (vmax, amax, ferr_limit, the soft limits, the
 * position) now reads differently in mm. A note lists them as they read
 * now, on stderr: nothing failed, but the operator did not ask for these.
 */
static int scale_note(struct ctl *c, const struct ctl_plan *p,
		      double cur[SH2000_AXES + 1][SH2000_GP_END])
{
	struct sh2000_status st;
	int r;

	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		double k, was = cur[a][SH2000_P_SCALE];
		char note[768];
		size_t n = 0;

		if (!p->set[a][SH2000_P_SCALE] || p->v[a][SH2000_P_SCALE] == was)
			continue;
		k = was / p->v[a][SH2000_P_SCALE];
		for (unsigned int id = 0; id < SH2000_AXIS_PARAMS && n < sizeof(note); id++)
			if (sh2000_param_lookup(id) && ctl_param_is_mm(id) && !p->set[a][id])
				n += (size_t)snprintf(note + n, sizeof(note) - n, "%s %g %s, ",
						      sh2000_param_lookup(id)->name,
						      cur[a][id] * k, sh2000_param_unit(id));
		if ((r = sh2000_poll(c->h, &st)) < 0)
			return sh2000_tool_fail(c->h, r, "status");
		if (n < sizeof(note))
			snprintf(note + n, sizeof(note) - n, "position %g mm",
				 st.axis[a].state & SH2000_AXIS_ENABLED ?
				 st.axis[a].cmd_mm : st.axis[a].pos_mm);
		sh2000_tool_msg("%s: note: %s scale %g counts/mm (was %g): the card keeps lengths in counts, so the ones not set now read %s",
				sh2000_device(c->h), ctl_plan_section(a),
				p->v[a][SH2000_P_SCALE], was, note);
	}
	return 0;
}

/* "[x]\nname = value  # unit" for every parameter of section s. */
static int print_section(struct ctl *c, FILE *f, unsigned int s)
{
	unsigned int lo = s == CTL_SECT_GLOBAL ? SH2000_GP_FIRST : 0;
	unsigned int hi = s == CTL_SECT_GLOBAL ? SH2000_GP_END : SH2000_AXIS_PARAMS;

	fprintf(f, "[%s]\n", ctl_plan_section(s));
	for (unsigned int id = lo; id < hi; id++) {
		double v;
		int r;

		if (!sh2000_param_lookup(id) || !ctl_card_has(c, id))
			continue;	/* not on this card's protocol */
		r = sh2000_param_get(c->h, s == CTL_SECT_GLOBAL ? SH2000_GLOBAL : (int)s,
				     id, &v);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "get parameter");
		sh2000_tool_param_line(f, id, v);
	}
	return 0;
}

static int params_save(struct ctl *c, const char *path)
{
	char *text = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&text, &len);
	int r = 0;

	if (!m) {
		sh2000_tool_msg("params save: %s", strerror(errno));
		return SH2000_EXIT_CARD;
	}
	/* everything from the card first: a card that fails half-way must
	 * not cost the file it would have replaced */
	fprintf(m, "# SH-2000 parameters of %s (sh2000ctl params save)\n"
		   "# units: lengths mm, velocities mm/s, accelerations mm/s^2\n",
		sh2000_device(c->h));
	for (unsigned int s = 0; !r && s <= CTL_SECT_GLOBAL; s++) {
		unsigned int sec = s == 0 ? CTL_SECT_GLOBAL : s - 1;

		fprintf(m, "\n");
		r = print_section(c, m, sec);
	}
	if (fclose(m) != 0 && !r) {
		sh2000_tool_msg("params save: %s", strerror(errno));
		r = SH2000_EXIT_CARD;
	}
	if (r) {
		sh2000_tool_msg("%s: not written", path);
		free(text);
		return r;
	}
	r = sh2000_tool_write_text(path, text, len);
	free(text);
	return r;
}

int ctl_params(struct ctl *c, int argc, char **argv)
{
	double cur[SH2000_AXES + 1][SH2000_GP_END];
	struct ctl_plan *p;
	int r, sect, nset = 0, nget = 0;

	if (ctl_want_help(argc, argv))
		return 0;
	if (argc >= 2 && (!strcmp(argv[1], "load") || !strcmp(argv[1], "save"))) {
		if (argc != 3)
			return sh2000_tool_usage(argv[0], "params %s: needs one FILE",
						 argv[1]);
		if (!strcmp(argv[1], "save")) {
			r = ctl_open(c);
			return r ? r : params_save(c, argv[2]);
		}
		p = calloc(1, sizeof(*p));
		if (!p)
			return SH2000_EXIT_CARD;
		/* the file is read before the card is opened: a bad file never
		 * touches it */
		r = plan_read_file(p, argv[2]);
		if (!r)
			r = ctl_open(c);
		else
			r = SH2000_EXIT_CARD;
		if (!r)
			r = plan_check(c, p, cur);
		if (!r)
			r = plan_apply(c, p, cur);
		if (!r)
			r = scale_note(c, p, cur);
		else if (p->errors)
			sh2000_tool_msg("%s: nothing set", argv[2]);
		free(p);
		return r;
	}
	if (argc == 1) {
		r = ctl_open(c);
		return r ? r : params_save(c, "-");
	}
	sect = !strcmp(argv[1], "global") ? (int)CTL_SECT_GLOBAL : sh2000_tool_axis(argv[1]);
	if (sect < 0)
		return sh2000_tool_usage(argv[0],
			"params: '%s' is not an axis (x y z a), 'global', 'load' or 'save'",
			argv[1]);
	for (int i = 2; i < argc; i++) {
		if (strchr(argv[i], '=')) {
			nset++;
			continue;
		}
		nget++;
		if (sh2000_param_id(argv[i]) < 0)
			return sh2000_tool_usage(argv[0], "params: unknown parameter '%s'",
						 argv[i]);
	}
	if (nset && nget)
		return sh2000_tool_usage(argv[0],
			"params: either get (NAME...) or set (NAME=VALUE...), not both");
	if (nget == 0 && nset == 0) {
		r = ctl_open(c);
		return r ? r : print_section(c, stdout, (unsigned int)sect);
	}
	if (nget) {
		r = ctl_open(c);
		for (int i = 2; !r && i < argc; i++) {
			int id = sh2000_param_id(argv[i]);
			char val[64];
			double v;

			if ((sect == CTL_SECT_GLOBAL) != (id >= SH2000_GP_FIRST))
				return sh2000_tool_usage(argv[0], "params: %s is %s parameter",
					argv[i], id >= SH2000_GP_FIRST ?
					"a global (use 'params global')" : "an axis");
			r = sh2000_param_get(c->h, sect == CTL_SECT_GLOBAL ? SH2000_GLOBAL : sect,
					     (unsigned int)id, &v);
			if (r < 0)
				return sh2000_tool_fail(c->h, r, "get parameter");
			sh2000_tool_param_format(val, sizeof(val), (unsigned int)id, v);
			printf("%s = %s\n", argv[i], val);
		}
		return r;
	}
	p = calloc(1, sizeof(*p));
	if (!p)
		return SH2000_EXIT_CARD;
	for (int i = 2; i < argc; i++) {
		char *name = strdup(argv[i]), *eq = strchr(name, '=');

		*eq = '\0';
		ctl_plan_add(p, (unsigned int)sect, name, eq + 1, 0);
		free(name);
	}
	r = p->errors ? sh2000_tool_usage(argv[0], "params: nothing set") : ctl_open(c);
	if (!r)
		r = plan_check(c, p, cur);
	if (!r)
		r = plan_apply(c, p, cur);
	if (!r)
		r = scale_note(c, p, cur);
	free(p);
	return r;
}
