/* SPDX-License-Identifier: MIT */
/*
 * sh2000ctl gather: the card records chosen signals of some axes every
 * PERIOD servo cycles (protocol 1.2, libsh2000's sh2000_gather_*), and the
 * record is written as CSV: a header row naming each column's axis, signal
 * and unit, then one row per sample with its time from the trigger. The
 * whole record is read before the file is written, so a failed read costs
 * no file. --no-wait only arms (for a chain that then moves: the in-process
 * `sim` card runs only inside this program), --read only waits and writes.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctl.h"

enum gather_mode { G_ALL, G_NO_WAIT, G_READ };

struct gather_args {
	struct sh2000_gather_config gc;
	unsigned int axes;		/* mask, bit n: axis n */
	unsigned int signals;		/* mask of 1 << SH2000_GS_* */
	const char *output;		/* "-": stdout */
	double timeout_s;		/* for the trigger and the record */
	enum gather_mode mode;
	int configured;			/* an option of the record was given */
};

/* "setpoint,encoder" or "all" -> mask; -1 with the bad name in *bad. */
static int signal_list(const char *s, char *bad, size_t badlen)
{
	char buf[256], *tok, *save = NULL;
	int mask = 0;

	if (!strcmp(s, "all"))
		return (1 << SH2000_GATHER_SIGNALS) - 1;
	snprintf(buf, sizeof(buf), "%s", s);
	for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		const struct sh2000_gather_signal_info *si =
			sh2000_gather_signal_by_name(tok);

		if (!si) {
			snprintf(bad, badlen, "%s", tok);
			return -1;
		}
		mask |= 1 << si->id;
	}
	if (!mask)
		snprintf(bad, badlen, "%s", s);
	return mask ? mask : -1;
}

static int trigger_of(const char *s)
{
	static const char *const n[] = { "now", "motion", "fault" };

	for (int i = 0; i < 3; i++)
		if (!strcmp(s, n[i]))
			return i;
	return -1;
}

/* One option with a value (k > 0 from ctl_opt_value) into *g. */
static int gather_value(struct gather_args *g, const char *opt, const char *v,
			const char *sub)
{
	char bad[256];
	long l;
	int m;

	if (!strcmp(opt, "axis")) {
		m = sh2000_tool_axes(v);
		if (m < 0)
			return sh2000_tool_usage(sub, "gather: --axis '%s': not an axis list (x, x,y, xyz or all)", v);
		g->axes = (unsigned int)m;
	} else if (!strcmp(opt, "signals")) {
		m = signal_list(v, bad, sizeof(bad));
		if (m < 0)
			return sh2000_tool_usage(sub, "gather: --signals: '%s' is not a signal (setpoint encoder ferr dac pid_p pid_i pid_d ff velocity setpoint_vel, or all)", bad);
		g->signals = (unsigned int)m;
	} else if (!strcmp(opt, "trigger")) {
		m = trigger_of(v);
		if (m < 0)
			return sh2000_tool_usage(sub, "gather: --trigger '%s': now, motion or fault", v);
		g->gc.trigger = (unsigned int)m;
	} else if (!strcmp(opt, "timeout")) {
		if (sh2000_tool_double(v, &g->timeout_s) < 0 || g->timeout_s <= 0 ||
		    g->timeout_s > 86400)
			return sh2000_tool_usage(sub, "gather: --timeout '%s': seconds, above 0 and at most 86400", v);
	} else if (!strcmp(opt, "output")) {
		if (!*v)
			return sh2000_tool_usage(sub, "gather: --output: empty file name");
		g->output = v;
	} else {
		unsigned long max = !strcmp(opt, "period") ? 65535 : SH2000_GATHER_BUFFER_VALUES;
		long min = !strcmp(opt, "pretrigger") ? 0 : 1;

		if (sh2000_tool_long(v, min, (long)max, &l) < 0)
			return sh2000_tool_usage(sub, "gather: --%s '%s': a whole number %ld..%lu",
						 opt, v, min, max);
		if (!strcmp(opt, "period"))
			g->gc.period = (unsigned int)l;
		else if (!strcmp(opt, "samples"))
			g->gc.samples = (uint32_t)l;
		else
			g->gc.pretrigger = (uint32_t)l;
	}
	return 0;
}

static int gather_args(struct gather_args *g, int argc, char **argv)
{
	static const char *const opts[] = { "axis", "signals", "period",
		"samples", "trigger", "pretrigger", "timeout", "output" };
	static const char shorts[] = "as\0\0\0\0\0o";

	memset(g, 0, sizeof(*g));
	sh2000_gather_config_default(&g->gc);
	g->axes = 1;
	g->signals = 1u << SH2000_GS_SETPOINT | 1u << SH2000_GS_ENCODER |
		     1u << SH2000_GS_FERR | 1u << SH2000_GS_DAC;
	g->output = "-";
	g->timeout_s = 60;
	for (int i = 1; i < argc; i++) {
		char lng[32];
		const char *v;
		size_t o;
		int k = 0, r;

		if (!strcmp(argv[i], "--no-wait") || !strcmp(argv[i], "--read")) {
			g->mode = argv[i][2] == 'n' ? G_NO_WAIT : G_READ;
			continue;
		}
		for (o = 0; !k && o < sizeof(opts) / sizeof(opts[0]); o++) {
			snprintf(lng, sizeof(lng), "--%s", opts[o]);
			k = ctl_opt_value(argc, argv, &i, lng, shorts[o], &v);
		}
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (!k)
			return sh2000_tool_usage(argv[0], "gather: unexpected '%s'", argv[i]);
		o--;
		if (o < 6)
			g->configured = 1;
		r = gather_value(g, opts[o], v, argv[0]);
		if (r)
			return r;
	}
	if (g->mode == G_READ && g->configured)
		return sh2000_tool_usage(argv[0], "gather --read: the record is on the card already: only --output and --timeout");
	if (g->mode == G_NO_WAIT && strcmp(g->output, "-"))
		return sh2000_tool_usage(argv[0], "gather --no-wait writes nothing: --output belongs to 'gather --read'");
	for (unsigned int a = 0; a < SH2000_AXES; a++)
		g->gc.signals[a] = g->axes & (1u << a) ? g->signals : 0;
	return 0;
}

/* "x.setpoint[counts]" for value k of a sample. */
static void column_name(const struct sh2000_gather_info *gi, unsigned int k,
			char *buf, size_t len)
{
	const struct sh2000_gather_signal_info *si;
	unsigned int axis = 0, sig = 0;

	sh2000_gather_column(gi, k, &axis, &sig);
	si = sh2000_gather_signal_lookup(sig);
	snprintf(buf, len, "%c.%s[%s]", sh2000_tool_axis_name(axis),
		 si ? si->name : "?", si ? si->unit : "?");
}

/* The CSV of a whole record, into memory. */
static int write_csv(FILE *m, const struct sh2000_gather_info *gi,
		     const double *v)
{
	uint32_t t0 = gi->trigger_index == SH2000_GATHER_NO_TRIGGER ? 0 :
		      gi->trigger_index;
	char name[64];

	fprintf(m, "time[s]");
	for (unsigned int k = 0; k < gi->values; k++) {
		column_name(gi, k, name, sizeof(name));
		fprintf(m, ",%s", name);
	}
	fprintf(m, "\n");
	for (uint32_t s = 0; s < gi->samples; s++) {
		fprintf(m, "%.9g", ((double)s - (double)t0) * gi->sample_s);
		for (unsigned int k = 0; k < gi->values; k++)
			fprintf(m, ",%.10g", v[(size_t)s * gi->values + k]);
		fprintf(m, "\n");
	}
	return ferror(m) ? -1 : 0;
}

/* Wait for record rec, read all of it, then write the file. */
static int wait_and_write(struct ctl *c, const struct gather_args *g,
			  unsigned int rec)
{
	struct sh2000_gather_info gi;
	char *text = NULL;
	size_t len = 0;
	double *v;
	FILE *m;
	int r;

	r = sh2000_gather_wait(c->h, rec, &gi, (int)(g->timeout_s * 1000.0));
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "gather");
	v = malloc(((size_t)gi.samples * gi.values + 1) * sizeof(*v));
	if (!v) {
		sh2000_tool_msg("gather: %s", strerror(ENOMEM));
		return SH2000_EXIT_CARD;
	}
	r = sh2000_gather_read(c->h, &gi, 0, gi.samples, v);
	if (r < 0) {
		free(v);
		return sh2000_tool_fail(c->h, r, "gather");
	}
	m = open_memstream(&text, &len);
	r = !m || write_csv(m, &gi, v) < 0;
	if (m && fclose(m) != 0)
		r = 1;
	free(v);
	if (r) {
		sh2000_tool_msg("gather: %s: not written: %s", g->output, strerror(errno));
		free(text);
		return SH2000_EXIT_CARD;
	}
	r = sh2000_tool_write_text(g->output, text, len);
	free(text);
	return r;
}

int ctl_gather(struct ctl *c, int argc, char **argv)
{
	struct gather_args g;
	struct sh2000_gather_info gi;
	int r, rec;

	if (ctl_want_help(argc, argv))
		return 0;
	r = gather_args(&g, argc, argv);
	if (!r)
		r = ctl_open(c);
	if (r)
		return r;
	if (g.mode == G_READ) {
		r = sh2000_gather_info(c->h, &gi);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "gather");
		if (gi.state == SH2000_GATHER_OFF) {
			sh2000_tool_msg("%s: gather --read: no record on the card (arm one with 'gather --no-wait')",
					sh2000_device(c->h));
			return SH2000_EXIT_CARD;
		}
		return wait_and_write(c, &g, gi.record);
	}
	rec = sh2000_gather_start(c->h, &g.gc);
	if (rec < 0)
		return sh2000_tool_fail(c->h, rec, "gather");
	return g.mode == G_NO_WAIT ? 0 : wait_and_write(c, &g, (unsigned int)rec);
}
