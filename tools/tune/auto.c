/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune --auto: identify the plant (ident.c: it moves the axis
 * within the user's bounds and back), design PID + feed-forward for the
 * bandwidth and margin asked (design.c), print the old and new gains with
 * the margins each gives on the identified plant, then, as asked: nothing
 * (--dry-run), a parameter file (--save), the gains on the card all or
 * none (--apply) checked by a step test, and the step drawn or written
 * (--plot, --csv; the old gains are put back after it unless --apply);
 * with --plot also a chirp with the new gains (testruns.c), its Bode plot
 * beside the step's picture and its measured margins beside the design's.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <sh2000/run.h>

#include "autotune.h"
#include "ident.h"
#include "tune.h"

static void print_plant(const struct tune_ident_result *r, char an)
{
	const struct tune_plant *pl = &r->plant;

	printf("axis %c: identified from %.2f s of motion, at most %.3f mm from the start\n",
	       an, r->seconds, r->amplitude_mm);
	printf("plant gain g            %.6g counts/s^2 per DAC code\n", pl->g);
	printf("friction pole b/m       %.4g 1/s\n", pl->p);
	printf("dead time               %u servo cycles (%g ms)\n", pl->d,
	       pl->d * pl->T * 1e3);
	printf("fit residual            %.3g counts RMS (%.3g %% of the motion's, %zu samples)\n",
	       pl->resid, pl->resid_rel * 100, pl->samples);
}

static void print_margins(const char *what, const struct tune_design_margins *m)
{
	printf("%-24s", what);
	if (!m->stable) {
		printf("unstable\n");
		return;
	}
	printf("phase %.1f deg at %.1f Hz, gain ", m->pm_deg, m->wc_hz);
	if (isinf(m->gm_db))
		printf("infinite\n");
	else
		printf("%.1f dB at %.1f Hz\n", m->gm_db, m->wpc_hz);
}

/* Old and new, as the parameter file writes them (values that read
 * back as the same binary32 the card keeps). */
static void print_gains(const struct tune_gains *o, const struct tune_gains *n)
{
	static const unsigned int ids[] = { SH2000_P_KP, SH2000_P_TI, SH2000_P_TD,
					    SH2000_P_KVFF, SH2000_P_KAFF };
	const double ov[] = { o->kp, o->ti, o->td, o->kvff, o->kaff };
	const double nv[] = { n->kp, n->ti, n->td, n->kvff, n->kaff };

	printf("gain        old             new\n");
	for (unsigned int i = 0; i < 5; i++) {
		char a[64], b[64];

		sh2000_tool_param_format(a, sizeof(a), ids[i], ov[i]);
		sh2000_tool_param_format(b, sizeof(b), ids[i], nv[i]);
		printf("%-11s %-15s %-15s %s\n", sh2000_param_name(ids[i]), a, b,
		       sh2000_param_unit(ids[i]));
	}
}

/* The Bode plot's file beside the step's: FILE-bode.png for FILE.png. */
static void bode_name(char *out, size_t len, const char *plot)
{
	const char *dot = strrchr(plot, '.');
	const char *slash = strrchr(plot, '/');
	int stem = dot && (!slash || dot > slash) ? (int)(dot - plot) : (int)strlen(plot);

	snprintf(out, len, "%.*s-bode%s", stem, plot, plot + stem);
}

/* The new gains' predicted margins beside those a chirp measured. */
static void print_measured(const struct tune_design_margins *pred,
			   const struct tune_margins *meas, double f1_hz)
{
	printf("margins, new gains      predicted   measured (chirp)\n");
	printf("%-24s%-12.2f%.2f Hz\n", "crossover", pred->wc_hz, meas->wc_hz);
	printf("%-24s%-12.1f%.1f deg\n", "phase margin", pred->pm_deg, meas->pm_deg);
	printf("%-24s", "gain margin");
	if (isinf(pred->gm_db))
		printf("%-12s", "infinite");
	else
		printf("%-12.1f", pred->gm_db);
	if (isnan(meas->gm_db))
		printf("none measured (the sweep, to %g Hz, does not reach it)\n", f1_hz);
	else
		printf("%.1f dB\n", meas->gm_db);
}

/* A chirp around the predicted crossover with the gains now on the card:
 * its Bode plot beside the step's picture, the margins it measures beside
 * the design's. */
static int check_chirp(struct sh2000 *h, const struct tune_opts *o,
		       const struct tune_design_margins *pred, char *bode,
		       size_t len)
{
	struct tune_opts co = *o;
	struct tune_margins meas;
	struct sh2000_path_config pc;
	int r;

	if ((r = sh2000_run_path_config(h, &pc)) < 0)
		return sh2000_tool_fail(h, r, "get parameter");
	bode_name(bode, len, o->plot);
	co.test = TUNE_TEST_CHIRP;
	co.csv = NULL;
	co.plot = bode;
	co.f0_hz = fmax(1, pred->wc_hz / TUNE_AUTO_CHIRP_SPAN);
	co.f1_hz = fmin(pred->wc_hz * TUNE_AUTO_CHIRP_SPAN,
			TUNE_AUTO_CHIRP_TOP * tune_chirp_f1_max(pc.period_s / pc.fine_steps));
	co.duration_s = fmin(10, fmax(TUNE_CHIRP_DURATION, 4 / co.f0_hz));
	if ((r = tune_check_options(&co)))
		return r;
	printf("chirp with the new gains:\n");
	r = tune_run_chirp(h, &co, &meas);
	if (!r)
		print_measured(pred, &meas, co.f1_hz);
	return r;
}

/* The step test with the gains now on the card, reported (and drawn),
 * and with --plot a chirp's Bode plot and measured margins. */
static int check_gains(struct sh2000 *h, const struct tune_opts *o,
		       const struct tune_design_margins *pred)
{
	struct tune_opts so = *o;
	char bode[4096];
	int r;

	if (so.step_mm == 0)
		so.step_mm = TUNE_AUTO_STEP_MM;
	printf("step test with the new gains:\n");
	r = tune_run_step(h, &so, ", auto-tuned gains");
	if (!r && o->plot)
		r = check_chirp(h, o, pred, bode, sizeof(bode));
	return r;
}

/* The new gains on the card (all or none), the step test, and the old
 * ones back unless they are to stay. */
static int try_gains(struct sh2000 *h, const struct tune_opts *o,
		     const struct tune_gains *old, const struct tune_gains *gn,
		     const struct tune_design_margins *pred)
{
	char why[512];
	int r, r2;

	r = tune_gains_set(h, o->axis, gn, old, why, sizeof(why));
	if (r < 0) {
		sh2000_tool_msg("%s: the new gains were not applied: %s; the old gains are back",
				sh2000_device(h), why);
		return sh2000_tool_exit_code(r);
	}
	printf("%s\n", o->apply ? "the new gains are on the card" :
	       "the new gains are on the card for the step test only");
	r = check_gains(h, o, pred);
	if (o->apply)
		return r;
	r2 = tune_gains_set(h, o->axis, old, gn, why, sizeof(why));
	if (r2 < 0) {
		sh2000_tool_msg("%s: the old gains could not be put back: %s",
				sh2000_device(h), why);
		return r ? r : sh2000_tool_exit_code(r2);
	}
	printf("the old gains are back on the card\n");
	return r;
}

/* Identify, design, print, write as asked. */
static int identify_and_design(struct sh2000 *h, const struct tune_opts *o)
{
	struct tune_design_req req = { o->bandwidth_hz, o->margin_deg, o->gm_db };
	struct tune_ident_result id;
	struct tune_gains old, gn;
	struct tune_design_margins mo, mn;
	char why[512], an = sh2000_tool_axis_name(o->axis);
	int r;

	if ((r = tune_read_gains(h, o->axis, &old)) < 0)
		return sh2000_tool_fail(h, r, "get parameter");
	r = tune_ident(h, o, &id);
	if (r)
		return r;
	if (sh2000_tool_stop_asked()) {
		sh2000_tool_msg("%s: axis %c: stopped by a signal after the identification: nothing written",
				sh2000_device(h), an);
		return SH2000_EXIT_STOPPED;
	}
	print_plant(&id, an);
	if (tune_design(&id.plant, &req, &gn, &mn, why, sizeof(why)) < 0) {
		sh2000_tool_msg("%s: axis %c: %s; nothing written", sh2000_device(h),
				an, why);
		return SH2000_EXIT_CARD;
	}
	tune_margins_of(&id.plant, &old, &mo);
	printf("design                  %.1f Hz crossover%s, phase margin %g deg, gain margin %g dB asked\n",
	       mn.wc_hz, o->bandwidth_hz > 0 ? "" : " (the default for this plant)",
	       o->margin_deg, o->gm_db);
	print_gains(&old, &gn);
	print_margins("predicted, old gains", &mo);
	print_margins("predicted, new gains", &mn);
	if (o->dry_run) {
		printf("dry run: nothing written (the card's gains are as they were)\n");
		return 0;
	}
	if (o->save && (r = tune_gains_save(o->save, sh2000_device(h), o->axis, &gn)))
		return r;
	if (o->save)
		printf("saved to %s (sh2000ctl params load %s)\n", o->save, o->save);
	if (o->apply || o->plot || o->csv)
		return try_gains(h, o, &old, &gn, &mn);
	return 0;
}

int tune_auto(struct sh2000 *h, const struct tune_opts *o)
{
	/* the axis enabled (--enable) once for the identification, the step
	 * and the chirp: disabled between them it would drift, and each
	 * test would start elsewhere */
	struct tune_move m = { .h = h, .o = o, .a = o->axis, .name = "auto-tuning" };
	int r = tune_move_prepare(&m);
	char why[256];

	/* a bandwidth the servo rate cannot carry: refused before anything
	 * moves, by the design's rule */
	if (!r && tune_bandwidth_check(o->bandwidth_hz,
				       m.pc.period_s / m.pc.fine_steps,
				       why, sizeof(why)) < 0) {
		sh2000_tool_msg("%s: axis %c: %s: nothing moved", sh2000_device(h),
				sh2000_tool_axis_name(o->axis), why);
		r = SH2000_EXIT_CARD;
	}
	if (!r)
		r = identify_and_design(h, o);
	tune_move_end(&m);
	return r;
}
