// SPDX-License-Identifier: GPL-2.0-or-later
/*
 * drift_probe: what two cards driven by hal_sh2000 do against each other,
 * seen from outside LinuxCNC the way `sh2000ctl status` sees them (for the
 * drift test, tests/linuxcnc/drift).
 *
 *   drift_probe SECONDS WARMUP TARGET PERIOD_NS DEV0 DEV1
 *
 * For SECONDS it polls both cards in turn every 200 us and keeps every
 * status snapshot: the card's servo cycle, the fine set-point of axis x
 * and the queue's fill. After WARMUP seconds it judges:
 *
 * - fill: the records queued on each card at each new snapshot (the
 *   card's view, between its consumption and the host's push): the
 *   least and most of each second's median (the fill's centre, which is
 *   what the clocks move; a thread late by a few periods makes short
 *   dips), and of all snapshots, against TARGET;
 * - skew: where the users sees it, the time between the two cards' fine
 *   set-points for the same command. Each card's servo cycles are put on
 *   the PC's clock: a cycle has run when a poll shows it, so the polls'
 *   (cycle, time) pairs lie on or above the line time = a + b * cycle of
 *   the card's oscillator (above by the server's wake-up latency and the
 *   poll's phase); the lower envelope of a million polls is that line. On
 *   it, card 0's set-point at the time of each of card 1's snapshots,
 *   interpolated between its own, less card 1's, over card 0's velocity,
 *   is how far card 1 is behind (where the motion is fast, so the ratio is
 *   well defined). PERIOD_NS is the servo thread's period, the unit the
 *   skew is also printed in.
 *
 * Prints the figures and a last line
 *   RESULT fill0 MIN MAX fill1 MIN MAX skew_us MAX ppm0 P ppm1 P stopped N
 * (the fills: of the medians of each second)
 * Exits 0 when it could measure (whatever the figures), 1 otherwise.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"

#define POLL_NS		200000L	/* between two rounds of polls */
#define WINDOW_NS	10000000ull	/* a clock point per card per 10 ms */
#define BLOCK		100	/* clock points per envelope block (1 s) */

struct snap {
	uint64_t cycle;
	double x;		/* fine set-point of axis x, counts */
	int fill;
	int running;
};

/* One card: its snapshots and the lowest (time - nominal * cycle) of
 * each window, the points the clock line is fitted to. */
struct card {
	const char *dev;
	struct sh2000 *h;
	struct snap *s;
	size_t n, cap;
	double *pc, *pr;	/* cycle, residual */
	size_t np, capp;
	uint64_t win;		/* window of the pending point */
	double a, b;		/* time = a + (b0 + b) * cycle, ns */
};

static double b0 = 100000.0;	/* nominal servo cycle, ns (refined) */

static uint64_t mono_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

static void *grow(void *p, size_t *cap, size_t n, size_t size)
{
	if (n < *cap)
		return p;
	*cap = *cap ? *cap * 2 : 4096;
	p = realloc(p, *cap * size);
	if (!p) {
		fprintf(stderr, "drift_probe: out of memory\n");
		exit(1);
	}
	return p;
}

static void keep_clock_point(struct card *k, uint64_t t0, uint64_t t,
			     uint64_t cycle)
{
	uint64_t win = (t - t0) / WINDOW_NS;
	double r = (double)t - b0 * (double)cycle;

	if (k->np && win == k->win) {
		if (r < k->pr[k->np - 1]) {
			k->pr[k->np - 1] = r;
			k->pc[k->np - 1] = (double)cycle;
		}
		return;
	}
	if (k->np == k->capp) {
		size_t cap = k->capp;

		k->pc = grow(k->pc, &cap, k->np, sizeof(double));
		k->pr = grow(k->pr, &k->capp, k->np, sizeof(double));
	}
	k->pc[k->np] = (double)cycle;
	k->pr[k->np] = r;
	k->np++;
	k->win = win;
}

/*
 * The records the card holds: POSTED - TAIL (protocol 1.3), both the
 * card's. (The status' queue_fill counts from this handle's HEAD, which
 * only the program that streams knows.) TAIL is read on both sides of
 * POSTED, so a record consumed in between is not miscounted.
 */
static int card_fill(struct card *k, int *fill)
{
	uint16_t t0, posted, t1;
	int i;

	for (i = 0; i < 10; i++) {
		if (sh2000_ram_read(k->h, SH2000_W_TAIL, 1, &t0) < 0 ||
		    sh2000_ram_read(k->h, SH2000_W_POSTED, 1, &posted) < 0 ||
		    sh2000_ram_read(k->h, SH2000_W_TAIL, 1, &t1) < 0)
			return -1;
		if (t0 == t1) {
			*fill = (uint16_t)(posted - t0);
			return 0;
		}
	}
	return -1;
}

static int poll_card(struct card *k, uint64_t t0)
{
	struct sh2000_status st;
	uint64_t t, cycle;
	int fill = 0, r = sh2000_poll(k->h, &st);

	t = mono_ns();
	if (r >= 0 || r == -SH2000_EHEARTBEAT)
		r = card_fill(k, &fill) < 0 ? -1 : 0;
	if (r < 0) {
		fprintf(stderr, "drift_probe: %s: %s\n", k->dev,
			sh2000_last_error(k->h));
		return -1;
	}
	/* the live heartbeat is the cycle counter's low 16 bits, read
	 * before the snapshot (which may be a cycle newer): both cycles had
	 * run when the poll ended */
	cycle = st.card_cycle;
	if ((int16_t)(st.heartbeat - (uint16_t)st.card_cycle) > 0)
		cycle += (uint16_t)(st.heartbeat - (uint16_t)st.card_cycle);
	keep_clock_point(k, t0, t, cycle);
	if (k->n && st.card_cycle <= k->s[k->n - 1].cycle)
		return 0;
	k->s = grow(k->s, &k->cap, k->n, sizeof(*k->s));
	k->s[k->n].cycle = st.card_cycle;
	k->s[k->n].x = (double)st.axis[0].cmd_counts;
	k->s[k->n].fill = fill;
	k->s[k->n].running = st.card_state == SH2000_STATE_RUNNING;
	k->n++;
	return 0;
}

/* Least squares line r = a + b * c over the points with use[i]. */
static void fit(const double *c, const double *r, const char *use, size_t n,
		double *a, double *b)
{
	double sc = 0, sr = 0, scc = 0, scr = 0, m = 0;
	size_t i;

	for (i = 0; i < n; i++) {
		if (!use[i])
			continue;
		sc += c[i];
		sr += r[i];
		m++;
	}
	sc /= m;
	sr /= m;
	for (i = 0; i < n; i++) {
		if (!use[i])
			continue;
		scc += (c[i] - sc) * (c[i] - sc);
		scr += (c[i] - sc) * (r[i] - sr);
	}
	*b = scc > 0 ? scr / scc : 0;
	*a = sr - *b * sc;
}

/* The lower envelope of a card's clock points: fit, keep each block's
 * lowest point under the fit, fit those, three times. */
static void fit_clock(struct card *k)
{
	char *use = calloc(k->np ? k->np : 1, 1);
	size_t i, j;
	int it;

	if (!use)
		exit(1);
	memset(use, 1, k->np);
	fit(k->pc, k->pr, use, k->np, &k->a, &k->b);
	for (it = 0; it < 3; it++) {
		memset(use, 0, k->np);
		for (i = 0; i < k->np; i += BLOCK) {
			size_t best = i;

			for (j = i; j < k->np && j < i + BLOCK; j++)
				if (k->pr[j] - k->b * k->pc[j] <
				    k->pr[best] - k->b * k->pc[best])
					best = j;
			use[best] = 1;
		}
		fit(k->pc, k->pr, use, k->np, &k->a, &k->b);
	}
	free(use);
}

static double card_time(const struct card *k, uint64_t cycle)
{
	return k->a + (b0 + k->b) * (double)cycle;
}

#define WINDOWS		10	/* the run in tenths, for a timeline */

struct window {
	int mmin[2], mmax[2];		/* fill: medians of each second */
	double skew_max, skew_sum;
	long skews;
};

struct result {
	double t_from, t_len;		/* the judged part of the run, ns */
	struct window w[WINDOWS];
	int fmin[2], fmax[2];		/* every snapshot */
	int mmin[2], mmax[2];		/* the medians of each second */
	long outside[2], counted[2];	/* snapshots beyond target +- 2 */
	int stopped;
	double skew_max, skew_sum, vmin;
	long skews;
};

#define FILL_MAX	65		/* 0..64 records */

/* The median of a histogram of fills. */
static int median(const long *hist, long n)
{
	long seen = 0;
	int f;

	for (f = 0; f < FILL_MAX; f++) {
		seen += hist[f];
		if (2 * seen >= n)
			return f;
	}
	return FILL_MAX - 1;
}

/* The tenth of the run time t is in. */
static struct window *window_at(struct result *res, double t)
{
	int w = (int)((t - res->t_from) / res->t_len * WINDOWS);

	return &res->w[w < 0 ? 0 : w >= WINDOWS ? WINDOWS - 1 : w];
}

static void min_max(int v, int *lo, int *hi)
{
	if (v < *lo)
		*lo = v;
	if (v > *hi)
		*hi = v;
}

static void median_min_max(int i, const long *hist, long n, double t,
			   struct result *res)
{
	struct window *w = window_at(res, t);
	int m;

	if (!n)
		return;
	m = median(hist, n);
	min_max(m, &res->mmin[i], &res->mmax[i]);
	min_max(m, &w->mmin[i], &w->mmax[i]);
}

/*
 * The fill of each snapshot after t_from, and the median of each second.
 * A servo thread that runs late by a few periods (an ordinary process on
 * a busy machine) shows as a short dip of the fill by as many records;
 * what the clocks do shows in the fill's centre, which the medians
 * follow.
 */
static void judge_fill(const struct card *k, int i, double t_from, int target,
		       struct result *res)
{
	long hist[FILL_MAX] = { 0 }, n = 0;
	double win_end = t_from + 1e9;
	size_t j;

	res->fmin[i] = res->mmin[i] = 1 << 20;
	res->fmax[i] = res->mmax[i] = -1;
	for (j = 0; j < k->n; j++) {
		double t = card_time(k, k->s[j].cycle);
		int f = k->s[j].fill;

		if (t < t_from)
			continue;
		if (!k->s[j].running) {
			res->stopped++;
			continue;
		}
		if (t >= win_end) {
			median_min_max(i, hist, n, win_end - 1e9, res);
			memset(hist, 0, sizeof(hist));
			n = 0;
			while (t >= win_end)
				win_end += 1e9;
		}
		hist[f < FILL_MAX ? f : FILL_MAX - 1]++;
		n++;
		res->counted[i]++;
		if (f < target - 2 || f > target + 2)
			res->outside[i]++;
		if (f < res->fmin[i])
			res->fmin[i] = f;
		if (f > res->fmax[i])
			res->fmax[i] = f;
	}
	median_min_max(i, hist, n, win_end - 1e9, res);
}

/* Card 1's lag behind card 0 at each of its snapshots after t_from where
 * card 0 moves faster than half its top speed. */
static void judge_skew(const struct card *k0, const struct card *k1,
		       double t_from, struct result *res)
{
	double vtop = 0;
	size_t i, j = 0;

	for (i = 1; i < k0->n; i++) {
		double dt = card_time(k0, k0->s[i].cycle) -
			    card_time(k0, k0->s[i - 1].cycle);
		double v = fabs(k0->s[i].x - k0->s[i - 1].x) / dt;

		if (card_time(k0, k0->s[i].cycle) > t_from && v > vtop)
			vtop = v;
	}
	res->vmin = vtop / 2;
	if (!(vtop > 0))
		return;
	for (i = 0; i < k1->n; i++) {
		double t = card_time(k1, k1->s[i].cycle), t0, t1, v, x0;

		if (t < t_from || !k1->s[i].running)
			continue;
		while (j + 1 < k0->n && card_time(k0, k0->s[j + 1].cycle) < t)
			j++;
		if (j + 1 >= k0->n)
			break;
		t0 = card_time(k0, k0->s[j].cycle);
		t1 = card_time(k0, k0->s[j + 1].cycle);
		/* a gap in the polls: no interpolation across it */
		if (t0 > t || t1 - t0 > 3e6)
			continue;
		v = (k0->s[j + 1].x - k0->s[j].x) / (t1 - t0);
		if (fabs(v) < res->vmin)
			continue;
		x0 = k0->s[j].x + v * (t - t0);
		v = (x0 - k1->s[i].x) / v;	/* ns */
		res->skew_sum += v;
		res->skews++;
		if (fabs(v) > res->skew_max)
			res->skew_max = fabs(v);
		{
			struct window *w = window_at(res, t);

			w->skew_sum += v;
			w->skews++;
			if (fabs(v) > w->skew_max)
				w->skew_max = fabs(v);
		}
	}
}

int main(int argc, char **argv)
{
	struct card k[2];
	struct result res = { 0 };
	double seconds, warmup, period, t_from, ppm[2];
	uint64_t t0, end;
	int i, target;

	if (argc != 7) {
		fprintf(stderr, "usage: drift_probe SECONDS WARMUP TARGET PERIOD_NS DEV0 DEV1\n");
		return 2;
	}
	seconds = atof(argv[1]);
	warmup = atof(argv[2]);
	target = atoi(argv[3]);
	period = atof(argv[4]);
	memset(k, 0, sizeof(k));
	for (i = 0; i < 2; i++) {
		char msg[256];

		k[i].dev = argv[5 + i];
		if (sh2000_open(&k[i].h, k[i].dev, msg, sizeof(msg)) < 0) {
			fprintf(stderr, "drift_probe: %s\n", msg);
			return 1;
		}
		/* a served card on a busy machine may pause for a while */
		sh2000_set_heartbeat_limit(k[i].h, 1000000000ull);
	}
	t0 = mono_ns();
	end = t0 + (uint64_t)(seconds * 1e9);
	while (mono_ns() < end) {
		struct timespec ts = { 0, POLL_NS };

		for (i = 0; i < 2; i++)
			if (poll_card(&k[i], t0) < 0)
				return 1;
		nanosleep(&ts, NULL);
	}
	t_from = (double)t0 + warmup * 1e9;
	res.t_from = t_from;
	res.t_len = (seconds - warmup) * 1e9;
	for (i = 0; i < WINDOWS; i++) {
		res.w[i].mmin[0] = res.w[i].mmin[1] = 1 << 20;
		res.w[i].mmax[0] = res.w[i].mmax[1] = -1;
	}
	for (i = 0; i < 2; i++) {
		if (k[i].n < 100 || k[i].np < 2 * BLOCK) {
			fprintf(stderr, "drift_probe: %s: too few snapshots (%zu)\n",
				k[i].dev, k[i].n);
			return 1;
		}
		fit_clock(&k[i]);
		ppm[i] = ((b0 + k[i].b) / b0 - 1) * 1e6;
		judge_fill(&k[i], i, t_from, target, &res);
		printf("card %d (%s): %zu snapshots, servo cycle %.3f ns on the PC's clock; queue-fill (target %d): each second's median %d..%d, every snapshot %d..%d, %.3f %% of them beyond +-2\n",
		       i, k[i].dev, k[i].n, b0 + k[i].b, target, res.mmin[i],
		       res.mmax[i], res.fmin[i], res.fmax[i],
		       res.counted[i] ? 100.0 * (double)res.outside[i] /
					(double)res.counted[i] : 0.0);
	}
	printf("the cards' clocks against each other: %+.1f ppm\n",
	       ((b0 + k[1].b) / (b0 + k[0].b) - 1) * 1e6);
	judge_skew(&k[0], &k[1], t_from, &res);
	if (!res.skews) {
		fprintf(stderr, "drift_probe: no fast motion to measure the skew on\n");
		return 1;
	}
	printf("skew of card 1 behind card 0: max |skew| %.1f us = %.3f servo periods, mean %+.1f us (%ld snapshots at >= %.1f counts/ms)\n",
	       res.skew_max * 1e-3, res.skew_max / period,
	       res.skew_sum / (double)res.skews * 1e-3, res.skews,
	       res.vmin * 1e6);
	for (i = 0; i < WINDOWS; i++) {
		const struct window *w = &res.w[i];

		printf("  %5.0f..%5.0f s: fill medians %d..%d and %d..%d, skew max |%.1f| us, mean %+.1f us\n",
		       warmup + res.t_len * 1e-9 * i / WINDOWS,
		       warmup + res.t_len * 1e-9 * (i + 1) / WINDOWS,
		       w->mmin[0], w->mmax[0], w->mmin[1], w->mmax[1],
		       w->skew_max * 1e-3,
		       w->skews ? w->skew_sum / (double)w->skews * 1e-3 : 0.0);
	}
	printf("RESULT fill0 %d %d fill1 %d %d skew_us %.1f ppm0 %.1f ppm1 %.1f stopped %d\n",
	       res.mmin[0], res.mmax[0], res.mmin[1], res.mmax[1],
	       res.skew_max * 1e-3, ppm[0], ppm[1], res.stopped);
	for (i = 0; i < 2; i++)
		sh2000_close(k[i].h);
	return 0;
}
