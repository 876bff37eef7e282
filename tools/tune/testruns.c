/* SPDX-License-Identifier: MIT */
/*
 * The step, ramp and chirp tests as sh2000-tune runs them: the ramp's and
 * chirp's options and the checks that need no card (usage errors, exit 2,
 * nothing opened), the reports, CSV and pictures, and the check that the
 * axis is back where it started.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tune.h"

static int positive(const char *opt, const char *v, double *out)
{
	if (sh2000_tool_double(v, out) < 0 || !(*out > 0))
		return sh2000_tool_usage(NULL, "%s: '%s' is not a number above 0", opt, v);
	return 0;
}

/* "F0:F1", both frequencies above 0, F0 below F1. */
static int chirp_range(const char *v, struct tune_opts *o)
{
	const char *colon = strchr(v, ':');
	char f0[64];

	if (!colon || (size_t)(colon - v) >= sizeof(f0))
		return sh2000_tool_usage(NULL, "--chirp: '%s' is not F0:F1 (Hz)", v);
	memcpy(f0, v, (size_t)(colon - v));
	f0[colon - v] = '\0';
	if (sh2000_tool_double(f0, &o->f0_hz) < 0 || !(o->f0_hz > 0) ||
	    sh2000_tool_double(colon + 1, &o->f1_hz) < 0 || !(o->f1_hz > 0))
		return sh2000_tool_usage(NULL, "--chirp: '%s' is not F0:F1 with two frequencies above 0 Hz", v);
	if (!(o->f0_hz < o->f1_hz))
		return sh2000_tool_usage(NULL, "--chirp %s: F0 (%g Hz) must be below F1 (%g Hz)",
					 v, o->f0_hz, o->f1_hz);
	return 0;
}

int tune_parse_option(int c, const char *v, struct tune_opts *o)
{
	switch (c) {
	case 'r':
		o->test = TUNE_TEST_RAMP;
		if (sh2000_tool_double(v, &o->ramp_mms) < 0 || o->ramp_mms == 0)
			return sh2000_tool_usage(NULL, "--ramp: '%s' is not a speed other than 0 in mm/s", v);
		return 0;
	case 'C':
		o->test = TUNE_TEST_CHIRP;
		return chirp_range(v, o);
	case 't': return positive("--travel", v, &o->travel_mm);
	case 'A': return positive("--amplitude", v, &o->amplitude_mm);
	case 'a': return positive("--accel", v, &o->accel_mms2);
	default: return positive("--duration", v, &o->duration_s);
	}
}

int tune_check_options(struct tune_opts *o)
{
	double least;

	if (o->test != TUNE_TEST_CHIRP)
		return 0;
	if (!(o->travel_mm > 0))
		o->travel_mm = TUNE_CHIRP_TRAVEL;
	if (o->amplitude_mm > o->travel_mm)
		return sh2000_tool_usage(NULL, "--amplitude %g mm: beyond the travel window of %g mm from the start (--travel)",
					 o->amplitude_mm, o->travel_mm);
	/* a few periods of F0, so the sweep holds it at all */
	least = 3 / o->f0_hz;
	if (o->duration_s < least)
		return sh2000_tool_usage(NULL, "--duration %g s: a sweep from %g Hz needs at least %g s (3 periods of F0)",
					 o->duration_s, o->f0_hz, least);
	if (o->duration_s > 10)
		return sh2000_tool_usage(NULL, "--duration: at most 10 s");
	return 0;
}

/* The test's exit code, the axis checked back at start (also after an
 * abort). */
static int after(struct sh2000 *h, unsigned int axis, int r, double start)
{
	if (!r)
		return tune_check_back(h, axis, start);
	if (r == SH2000_EXIT_ABORTED && tune_check_back(h, axis, start))
		return SH2000_EXIT_CARD;
	return r;
}

int tune_write_csv(const char *path, void (*fn)(FILE *m, const void *ctx),
		   const void *ctx)
{
	char *text = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&text, &len);
	int r;

	if (!m) {
		sh2000_tool_msg("--csv %s: out of memory", path);
		return SH2000_EXIT_CARD;
	}
	fn(m, ctx);
	fclose(m);
	r = sh2000_tool_write_text(path, text, len);
	free(text);
	return r;
}

static void step_csv(FILE *m, const void *ctx)
{
	const struct tune_trace *tr = ctx;

	fprintf(m, "time[s],setpoint[counts],encoder[counts],dac[DAC codes]\n");
	for (size_t i = 0; i < tr->n; i++)
		fprintf(m, "%.9g,%.10g,%.10g,%.10g\n", tr->t[i], tr->sp[i],
			tr->enc[i], tr->dac[i]);
}

static void step_report(const struct tune_opts *o, const struct tune_trace *tr,
			const struct tune_metrics *m)
{
	char an = sh2000_tool_axis_name(o->axis);

	printf("axis %c: step %g mm (%.0f counts), held %g s\n", an, o->step_mm,
	       tr->end - tr->start, o->hold_s);
	printf("rise time (10-90 %%)     %.3f ms\n", m->rise_s * 1e3);
	printf("overshoot               %.0f counts (%.1f %%)\n", m->overshoot,
	       m->overshoot_pct);
	if (m->settled)
		printf("settling to %.0f counts   %.3f ms\n", TUNE_SETTLE_COUNTS,
		       m->settle_s * 1e3);
	else
		printf("settling to %.0f counts   not settled within the hold\n",
		       TUNE_SETTLE_COUNTS);
	printf("peak following error    %.1f counts\n", m->peak_ferr);
	printf("peak DAC                %.0f codes\n", m->peak_dac);
}

int tune_run_step(struct sh2000 *h, const struct tune_opts *o, const char *note)
{
	struct tune_trace tr;
	struct tune_metrics m;
	char title[160];
	int r = tune_step(h, o, &tr);

	if (!r) {
		if (tune_metrics(&tr, &m) < 0)
			sh2000_tool_msg("%s: the encoder never reached 90 %% of the step",
					sh2000_device(h));
		step_report(o, &tr, &m);
	}
	r = after(h, o->axis, r, tr.start);
	if (!r && o->csv)
		r = tune_write_csv(o->csv, step_csv, &tr);
	if (!r && o->plot) {
		snprintf(title, sizeof(title), "%s axis %c: step of %g mm%s",
			 sh2000_device(h), sh2000_tool_axis_name(o->axis), o->step_mm, note);
		r = tune_plot(&tr, &m, o->plot, title);
	}
	tune_trace_free(&tr);
	return r;
}

static void ramp_csv(FILE *m, const void *ctx)
{
	const struct tune_ramp *rp = ctx;

	fprintf(m, "time[s],setpoint[counts],encoder[counts],ferr[counts],dac[DAC codes],constant_speed\n");
	for (size_t i = 0; i < rp->n; i++)
		fprintf(m, "%.9g,%.10g,%.10g,%.9g,%.10g,%d\n", rp->t[i], rp->sp[i],
			rp->enc[i], rp->ferr[i], rp->dac[i], rp->cruise[i]);
}

static void ramp_report(const struct tune_opts *o, const struct tune_ramp *rp)
{
	double um = 1e3 / rp->counts_per_mm;

	printf("axis %c: ramp %g mm/s over %g mm (accelerating at %g mm/s^2)\n",
	       sh2000_tool_axis_name(o->axis), rp->speed_mms, rp->travel_mm,
	       rp->accel_mms2);
	printf("constant speed          %.1f ms\n",
	       rp->cruise_n * (rp->n > 1 ? rp->t[1] - rp->t[0] : 0) * 1e3);
	printf("constant-speed peak     %.2f counts  %.4f um\n", rp->cruise_peak,
	       rp->cruise_peak * um);
	printf("constant-speed RMS      %.2f counts  %.4f um\n", rp->cruise_rms,
	       rp->cruise_rms * um);
	printf("accelerating peak       %.2f counts  %.4f um\n", rp->accel_peak,
	       rp->accel_peak * um);
	printf("peak DAC                %.0f codes\n", rp->peak_dac);
}

int tune_run_ramp(struct sh2000 *h, const struct tune_opts *o)
{
	struct tune_ramp rp;
	char title[128];
	int r = tune_ramp(h, o, &rp);

	if (!r) {
		ramp_report(o, &rp);
		if (!rp.cruise_n)
			sh2000_tool_msg("%s: the set-point never held the ramp's speed", sh2000_device(h));
	}
	r = after(h, o->axis, r, rp.start);
	if (!r && o->csv)
		r = tune_write_csv(o->csv, ramp_csv, &rp);
	if (!r && o->plot) {
		snprintf(title, sizeof(title), "%s axis %c: ramp at %g mm/s",
			 sh2000_device(h), sh2000_tool_axis_name(o->axis), o->ramp_mms);
		r = tune_plot_ramp(&rp, o->plot, title);
	}
	tune_ramp_free(&rp);
	return r;
}

static double deg(double complex z)
{
	return carg(z) * 180 / M_PI;
}

static void chirp_csv(FILE *m, const void *ctx)
{
	const struct tune_fr *fr = ctx;

	fprintf(m, "frequency[Hz],plant[counts/code],plant_phase[deg],loop,loop_phase[deg],"
		"closed,closed_phase[deg],pid[codes/count],pid_phase[deg]\n");
	for (size_t i = 0; i < fr->n; i++)
		fprintf(m, "%.6g,%.6g,%.3f,%.6g,%.3f,%.6g,%.3f,%.6g,%.3f\n", fr->hz[i],
			cabs(fr->plant[i]), deg(fr->plant[i]), cabs(fr->loop[i]),
			deg(fr->loop[i]), cabs(fr->closed[i]), deg(fr->closed[i]),
			cabs(fr->ctrl[i]), deg(fr->ctrl[i]));
}

static void chirp_report(const struct tune_opts *o, const struct tune_fr *fr,
			 const struct tune_margins *m)
{
	const struct tune_gains *g = &fr->gains;

	printf("axis %c: chirp %.4g-%.4g Hz, amplitude %g mm (%.0f counts), %g s\n",
	       sh2000_tool_axis_name(o->axis), o->f0_hz, o->f1_hz, o->amplitude_mm,
	       o->amplitude_mm * fr->counts_per_mm, o->duration_s);
	printf("card's gains            kp %g codes/count, ti %g s, td %g s\n",
	       g->kp, g->ti, g->td);
	printf("response                %zu frequencies, sampled every %g ms\n",
	       fr->n, fr->sample_s * 1e3);
	if (fr->sweep_coarse_s != fr->coarse_s)
		printf("coarse period           %g ms for the sweep (the card's %g ms put back)\n",
		       fr->sweep_coarse_s * 1e3, fr->coarse_s * 1e3);
	if (isnan(m->wc_hz))
		printf("crossover               none measured (the loop gain does not fall through 0 dB)\n");
	else
		printf("crossover               %.2f Hz\nphase margin            %.1f deg\n",
		       m->wc_hz, m->pm_deg);
	if (isnan(m->gm_db))
		printf("gain margin             none measured (the sweep, to %g Hz, does not reach a phase of -180 deg)\n",
		       o->f1_hz);
	else
		printf("gain margin             %.1f dB at %.2f Hz\n", m->gm_db, m->w180_hz);
	if (!isnan(m->gm_low_db))
		printf("gain reduction margin   %.1f dB at %.2f Hz (the loop gain may fall that much: phase -180 deg below the crossover)\n",
		       -m->gm_low_db, m->w180_low_hz);
	if (isnan(m->bw_hz))
		printf("bandwidth (-3 dB)       beyond %g Hz\n", o->f1_hz);
	else
		printf("bandwidth (-3 dB)       %.2f Hz\n", m->bw_hz);
	printf("peak DAC                %.0f codes\n", fr->peak_dac);
}

int tune_run_chirp(struct sh2000 *h, const struct tune_opts *o,
		   struct tune_margins *measured)
{
	struct tune_fr fr;
	struct tune_margins m;
	char title[160];
	struct sh2000_status st;
	int r;

	/* the start, for the check afterwards */
	if ((r = sh2000_poll(h, &st)) < 0)
		return sh2000_tool_fail(h, r, "status");
	r = tune_chirp(h, o, &fr);
	if (!r) {
		tune_margins(&fr, &m);
		chirp_report(o, &fr, &m);
		if (measured)
			*measured = m;
		if (fr.weak)
			sh2000_tool_msg("%s: %zu of %zu frequencies (%.4g-%.4g Hz) left out: the gains and feed-forward follow the set-point there with less DAC than the PID gives for %g counts of error, so the encoder's quantisation drowns the plant (a larger --amplitude, or a higher F0)",
					sh2000_device(h), fr.weak, fr.weak + fr.n,
					fr.weak_lo_hz, fr.weak_hi_hz, TUNE_FR_MIN_ERR);
		if (fr.dac_saturated)
			sh2000_tool_msg("%s: the DAC reached its bound during the sweep: the response is not linear there (a smaller --amplitude or --accel)",
					sh2000_device(h));
	}
	r = after(h, o->axis, r, (double)st.axis[o->axis].cmd_counts);
	if (!r && o->csv)
		r = tune_write_csv(o->csv, chirp_csv, &fr);
	if (!r && o->plot) {
		snprintf(title, sizeof(title), "%s axis %c: chirp %.4g-%.4g Hz, %g mm",
			 sh2000_device(h), sh2000_tool_axis_name(o->axis), o->f0_hz,
			 o->f1_hz, o->amplitude_mm);
		r = tune_plot_bode(&fr, &m, o->plot, title);
	}
	return r;
}
