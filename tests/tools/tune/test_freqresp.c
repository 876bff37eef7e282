/* SPDX-License-Identifier: MIT */
/*
 * sh2000-tune's identification against answers known in closed form:
 *  - the DTFT ratio of a rest-to-rest record is a filter's exact response;
 *  - margins of loops whose crossover, phase margin, gain margins and
 *    bandwidth are known analytically;
 *  - on the simulated card (`sim`, virtual time, docs/cardmodel.md "Plant":
 *    m 2 kg, b 20 N s/m, k_F 20 N/V, 10/32768 V per code, 1e8 counts/m),
 *    the chirp's measured plant against the analytic one: the double
 *    integrator with viscous friction g / (s (s + b/m)) under the DAC's
 *    zero-order hold, sampled at the servo period, the DAC written in the
 *    cycle that read the encoder (no further delay); and the margins from
 *    the measured loop against the analytic loop's (the sweep to 3 kHz:
 *    the gain margin of the default gains lies near 2.5 kHz, so the
 *    card's coarse period is shortened for it, chirptiming.c);
 *  - the ramp's following error against the card model's own probe of
 *    every servo cycle (set-point and encoder, not the gathered record).
 * Lines starting with '#' are the measured figures (docs/tools.md).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <sh2000/sim.h>

#include "tune.h"

#define PLANT_A	(20.0 / 2.0)			/* b/m, 1/s */
#define PLANT_G	(20.0 * 10 / 32768 / 2 * 1e8)	/* counts/s^2 per code */

/* ---- the estimator and the margins on closed forms ---- */

static void ratio_is_exact(void **state)
{
	enum { N = 6000 };
	static double x[N], y[N];
	double hz[8], ts = 1e-4;
	double complex out[8];

	(void)state;
	/* a swept input from rest, back at rest from sample 4000; y through
	 * H(z) = 0.3 z^-1 / (1 - 0.7 z^-1), decayed by the end */
	for (int k = 0; k < N; k++) {
		double t = k * ts;

		x[k] = k < 4000 ? sin(2 * M_PI * (20 * t + 300 * t * t)) * sin(M_PI * k / 4000) : 0;
		y[k] = k ? 0.7 * y[k - 1] + 0.3 * x[k - 1] : 0;
	}
	tune_fr_grid(20, 250, 8, hz);
	tune_fr_ratio(x, y, N, ts, hz, 8, out);
	for (int i = 0; i < 8; i++) {
		double complex z1 = cexp(-I * 2 * M_PI * hz[i] * ts);
		double complex h = 0.3 * z1 / (1 - 0.7 * z1);

		/* exact where one bin is taken (below 20 bins' width), the
		 * band's weighted mean of H within 5 % of f above (0.17 % off
		 * at the sweep's end, where its energy falls) */
		if (hz[i] < 20 / (N * ts))
			assert_true(cabs(out[i] - h) < 1e-12 * cabs(h));
		else
			assert_true(cabs(out[i] - h) < 5e-3 * cabs(h));
	}
}

static void fill(struct tune_fr *fr, double f0, double f1,
		 double complex (*l)(double w))
{
	memset(fr, 0, sizeof(*fr));
	fr->n = TUNE_FR_POINTS;
	tune_fr_grid(f0, f1, fr->n, fr->hz);
	for (size_t i = 0; i < fr->n; i++)
		fr->loop[i] = fr->closed[i] = l(2 * M_PI * fr->hz[i]);
}

/* k e^(-jw tau) / (jw): crossover at k, PM 90 - k tau, -180 at w tau = pi/2 */
static double complex delayed_integrator(double w)
{
	return 2 * M_PI * 100 * cexp(-I * w * 5e-4) / (I * w);
}

static double complex integrator(double w)
{
	return 2 * M_PI * 100 / (I * w);
}

/* K (1 + jw/a)^2 / (jw)^3, a = 2 pi 20: -180 at w = a with |L| = 2K/a^3 */
static double complex conditional(double w)
{
	double a = 2 * M_PI * 20;
	double complex s = I * w;

	return a * a * 2 * M_PI * 200 * (1 + s / a) * (1 + s / a) / (s * s * s);
}

static void margins_closed_forms(void **state)
{
	struct tune_fr fr;
	struct tune_margins m;

	(void)state;
	fill(&fr, 10, 1000, delayed_integrator);
	assert_int_equal(tune_margins(&fr, &m), 0);
	assert_true(fabs(m.wc_hz - 100) < 0.1);
	assert_true(fabs(m.pm_deg - (90 - 2 * M_PI * 100 * 5e-4 * 180 / M_PI)) < 0.3);
	assert_true(fabs(m.w180_hz - 500) < 5);
	assert_true(fabs(m.gm_db - 20 * log10(5)) < 0.1);
	assert_true(isnan(m.gm_low_db));

	fill(&fr, 10, 1000, integrator);
	assert_int_equal(tune_margins(&fr, &m), 0);
	assert_true(fabs(m.bw_hz - 100) < 1);	/* L/(1+L) = k / (s + k) */
	assert_true(isnan(m.gm_db) && isnan(m.w180_hz));
	assert_true(fabs(m.pm_deg - 90) < 1e-6);

	fill(&fr, 5, 2000, conditional);
	assert_int_equal(tune_margins(&fr, &m), 0);
	assert_true(fabs(m.w180_low_hz - 20) < 0.3);
	assert_true(fabs(m.gm_low_db + 20 * log10(20)) < 0.1);
	assert_true(isnan(m.gm_db));

	/* no crossover in the band */
	fill(&fr, 1, 10, integrator);
	assert_int_equal(tune_margins(&fr, &m), -1);
	assert_true(isnan(m.wc_hz) && isnan(m.pm_deg));
}

/* ---- on the simulated card ---- */

/* The ZOH discretisation of g / (s (s + a)) at f, servo period T. */
static double complex analytic_plant(double f, double T)
{
	double a = PLANT_A, e = exp(-a * T);
	double complex z = cexp(I * 2 * M_PI * f * T);

	return PLANT_G * ((a * T - 1 + e) * z + (1 - e - a * T * e)) /
	       (a * a * (z - 1) * (z - e));
}

static struct sh2000 *open_sim(void)
{
	struct sh2000 *h = NULL;
	char msg[256];

	sh2000_tool_init("test_freqresp");
	assert_int_equal(sh2000_open(&h, "sim", msg, sizeof(msg)), 0);
	return h;
}

/* The card's timing and the axis' limits the tests change for a while. */
static void limits(struct sh2000 *h, double v[4])
{
	assert_int_equal(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_COARSE_PERIOD_US, &v[0]), 0);
	assert_int_equal(sh2000_param_get(h, SH2000_GLOBAL, SH2000_GP_FINE_STEPS, &v[1]), 0);
	assert_int_equal(sh2000_param_get(h, 0, SH2000_P_FERR_LIMIT, &v[2]), 0);
	assert_int_equal(sh2000_param_get(h, 0, SH2000_P_DAC_LIMIT, &v[3]), 0);
}

static void chirp_matches_plant(void **state)
{
	struct tune_opts o = { .device_arg = "sim", .axis = 0, .test = TUNE_TEST_CHIRP,
			       .ferr_max_mm = 0.1, .enable = 1, .f0_hz = 5, .f1_hz = 3000,
			       .amplitude_mm = TUNE_CHIRP_AMPLITUDE,
			       .duration_s = TUNE_CHIRP_DURATION, .travel_mm = 1 };
	struct sh2000 *h = open_sim();
	struct tune_fr fr, an;
	struct tune_margins m, ma;
	double worst_mag = 0, worst_ph = 0, band_mag = 0, band_ph = 0;
	double before[4], after[4];
	struct sh2000_status st;

	(void)state;
	limits(h, before);
	assert_int_equal(tune_chirp(h, &o, &fr), 0);
	/* the coarse period (shortened for the sweep) and the limits back,
	 * the axis at its start */
	limits(h, after);
	assert_memory_equal(before, after, sizeof(before));
	assert_int_equal(sh2000_poll(h, &st), 0);
	assert_int_equal(st.axis[0].cmd_counts, 0);
	assert_true(fr.sample_s == fr.servo_s);
	assert_int_equal(fr.n, TUNE_FR_POINTS);
	assert_false(fr.dac_saturated);
	an = fr;
	for (size_t i = 0; i < fr.n; i++) {
		double complex p = analytic_plant(fr.hz[i], fr.servo_s);
		double mag = fabs(cabs(fr.plant[i]) / cabs(p) - 1);
		double ph = fabs(carg(fr.plant[i] / p)) * 180 / M_PI;

		worst_mag = fmax(worst_mag, mag);
		worst_ph = fmax(worst_ph, ph);
		if (fr.hz[i] >= 10 && fr.hz[i] <= 1000) {
			band_mag = fmax(band_mag, mag);
			band_ph = fmax(band_ph, ph);
		}
		an.plant[i] = p;
		an.loop[i] = fr.ctrl[i] * p;
	}
	printf("# plant vs analytic, 10-1000 Hz: magnitude within %.3f %%, phase within %.3f deg\n",
	       band_mag * 100, band_ph);
	printf("# plant vs analytic, 5-3000 Hz: magnitude within %.3f %%, phase within %.3f deg\n",
	       worst_mag * 100, worst_ph);
	assert_true(band_mag < 0.005 && band_ph < 0.3);
	assert_true(worst_mag < 0.06 && worst_ph < 3);
	/* the margins: measured against analytic, on the same frequencies */
	assert_int_equal(tune_margins(&fr, &m), 0);
	assert_int_equal(tune_margins(&an, &ma), 0);
	printf("# measured: crossover %.2f Hz, PM %.2f deg, GM %.2f dB at %.1f Hz, gain-reduction margin %.2f dB at %.2f Hz, bandwidth %.2f Hz\n",
	       m.wc_hz, m.pm_deg, m.gm_db, m.w180_hz, m.gm_low_db, m.w180_low_hz, m.bw_hz);
	printf("# analytic: crossover %.2f Hz, PM %.2f deg, GM %.2f dB at %.1f Hz, gain-reduction margin %.2f dB at %.2f Hz, bandwidth %.2f Hz\n",
	       ma.wc_hz, ma.pm_deg, ma.gm_db, ma.w180_hz, ma.gm_low_db, ma.w180_low_hz, ma.bw_hz);
	assert_true(fabs(m.gm_db - ma.gm_db) < 0.5);
	assert_true(fabs(m.w180_hz / ma.w180_hz - 1) < 0.02);
	assert_true(fabs(m.wc_hz / ma.wc_hz - 1) < 0.01);
	assert_true(fabs(m.pm_deg - ma.pm_deg) < 0.5);
	assert_true(fabs(m.gm_low_db - ma.gm_low_db) < 0.2);
	assert_true(fabs(m.w180_low_hz / ma.w180_low_hz - 1) < 0.01);
	assert_true(fabs(m.bw_hz / ma.bw_hz - 1) < 0.01);
	sh2000_close(h);
}

struct probe_log {
	size_t n, cap;
	double *cmd, *act;
};

static void log_cycle(void *ctx, const struct sh2000_probe *p)
{
	struct probe_log *l = ctx;

	if (l->n == l->cap) {
		l->cap = l->cap ? 2 * l->cap : 65536;
		l->cmd = realloc(l->cmd, l->cap * sizeof(double));
		l->act = realloc(l->act, l->cap * sizeof(double));
		assert_non_null(l->cmd);
		assert_non_null(l->act);
	}
	l->cmd[l->n] = p->axis[0].fine_cmd;
	l->act[l->n++] = p->axis[0].actual;
}

/* The figures of the way out from the probe of every cycle, cruise where
 * the set-point's own speed is the ramp's (0.2 %, and the speed one count
 * per cycle makes, as ramp.c allows for its rounded record). */
static void probe_figures(const struct probe_log *l, double v, double ts,
			  double *peak, double *rms, double *accel)
{
	double sum = 0;
	size_t n = 0;

	*peak = *accel = 0;
	for (size_t i = 1; i + 1 < l->n; i++) {
		double s = (l->cmd[i + 1] - l->cmd[i - 1]) / (2 * ts);
		double e = fabs(l->cmd[i] - l->act[i]);

		if (s * v < 0)
			break;	/* on the way back */
		if (fabs(s - v) <= 0.002 * fabs(v) + 1 / ts) {
			n++;
			sum += e * e;
			*peak = fmax(*peak, e);
		} else if (lrint(l->cmd[i]) != lrint(l->cmd[i - 1])) {
			/* moving, as the record's rounded set-point shows it */
			*accel = fmax(*accel, e);
		}
	}
	*rms = n ? sqrt(sum / n) : NAN;
}

static void ramp_matches_probe(void **state)
{
	static const double speeds[] = { 100, 300 };

	(void)state;
	for (int k = 0; k < 2; k++) {
		struct tune_opts o = { .device_arg = "sim", .axis = 0, .test = TUNE_TEST_RAMP,
				       .ferr_max_mm = 0.1, .enable = 1, .ramp_mms = speeds[k] };
		struct sh2000 *h = open_sim();
		struct probe_log l = { 0 };
		struct tune_ramp rp;
		double peak, rms, accel, ts;

		assert_int_equal(sh2000_sim_set_observer(h, log_cycle, &l), 0);
		assert_int_equal(tune_ramp(h, &o, &rp), 0);
		sh2000_sim_set_observer(h, NULL, NULL);
		ts = rp.t[1] - rp.t[0];
		assert_true(fabs(ts - 1e-4) < 1e-9);	/* every cycle gathered */
		probe_figures(&l, speeds[k] * rp.counts_per_mm, ts, &peak, &rms, &accel);
		printf("# ramp %g mm/s: constant speed peak %.2f counts (probe %.2f), RMS %.3f (probe %.3f); accelerating peak %.2f (probe %.2f)\n",
		       speeds[k], rp.cruise_peak, peak, rp.cruise_rms, rms,
		       rp.accel_peak, accel);
		assert_true(rp.cruise_n > 100);
		assert_true(fabs(rp.cruise_peak - peak) <= 0.5);
		assert_true(fabs(rp.cruise_rms - rms) <= 0.05 * rms + 0.1);
		assert_true(fabs(rp.accel_peak - accel) <= 0.5);
		tune_ramp_free(&rp);
		free(l.cmd);
		free(l.act);
		sh2000_close(h);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ratio_is_exact),
		cmocka_unit_test(margins_closed_forms),
		cmocka_unit_test(chirp_matches_plant),
		cmocka_unit_test(ramp_matches_probe),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
