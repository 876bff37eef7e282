// SPDX-License-Identifier: GPL-2.0 OR MIT
/*
 * Checks an sh2000-upload --trace CSV of tests/kernel/stack.ngc against the
 * part's geometry; prints one "KTEST ok|FAIL stack: ..." line per check and
 * exits 1 when any failed. Static, for the VM's initramfs (busybox awk there
 * has no math functions); it runs on a host trace just as well.
 *
 *	ktrace TRACE.csv FERR_MM MIN_ROWS MIN_CIRCLE_ROWS
 *
 * The part (mm, XY plane; z and a never move):
 *	line   (0,0) -> (10,0)
 *	circle centre (10,5), R 5, counter-clockwise from (10,0) back to (10,0),
 *	       tangent to the line before it
 *	line   (10,0) -> (4,3): a corner of 153 degrees at (10,0)
 *
 * Tolerances (mm) and why:
 *	CMD_TOL  0.012  the set-point may leave the programmed path by the
 *			planner's corner tolerance (0.01) at the one corner, plus
 *			the compensated B-spline's error (< 1 um, tests/planner)
 *			and the rounding to counts (10 nm);
 *	CIRC_TOL 0.002  on the circle away from the junction the set-point is
 *			within 1 um of R (compensated B-spline) and one count;
 *	FERR            the largest following error allowed in any row, set
 *			by the caller for the servo timing in use (tests/kernel/
 *			init argues its 5 um); a row's set-point and encoder are
 *			from the same servo cycle (one snapshot), so sampling adds
 *			nothing and the encoder is within CMD_TOL + FERR of the
 *			path and CIRC_TOL + FERR of R (triangle inequality);
 *	END_CMD  0.0005 the last row's set-point is the programmed end (the
 *			planner stops exactly; the trace prints 1 nm steps);
 *	END_ACT  0.003  the last row's encoder: the card is at rest and the
 *			servo holds it within a few counts.
 * Rows are the status snapshots the host happened to poll, so the circle is
 * checked for coverage per octant as well as for a row count.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CMD_TOL		0.012
#define CIRC_TOL	0.002
#define END_CMD		0.0005
#define END_ACT		0.003
#define HEADER		"t,cmd_x,act_x,cmd_y,act_y,cmd_z,act_z,cmd_a,act_a"

static int g_failed;

static void check(int ok, const char *good, const char *bad)
{
	if (ok) {
		printf("KTEST ok stack: %s\n", good);
	} else {
		printf("KTEST FAIL stack: %s\n", bad);
		g_failed++;
	}
}

/* distance of (x,y) to the segment (ax,ay)-(bx,by) */
static double dseg(double x, double y, double ax, double ay, double bx,
		   double by)
{
	double dx = bx - ax, dy = by - ay;
	double u = ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy);

	if (u < 0)
		u = 0;
	if (u > 1)
		u = 1;
	return hypot(x - ax - u * dx, y - ay - u * dy);
}

static double dcircle(double x, double y)
{
	return fabs(hypot(x - 10, y - 5) - 5);
}

static double dpath(double x, double y)
{
	double d = dseg(x, y, 0, 0, 10, 0), e = dcircle(x, y);

	if (e < d)
		d = e;
	e = dseg(x, y, 10, 0, 4, 3);
	return e < d ? e : d;
}

int main(int argc, char **argv)
{
	double ferr, t = 0, t0 = 0, lt = 0, v[9], last[9] = { 0 };
	double mcmd = 0, mcmd_t = 0, mact = 0, mact_t = 0, mferr = 0;
	double mferr_t = 0, mza = 0, mrc = 0, mra = 0, d, dc, da;
	long min_rows, min_circle, rows = 0, bad = 0, tback = 0, ncirc = 0;
	int oct[8] = { 0 }, noct = 0, i;
	char line[512], good[300], badmsg[300];
	FILE *f;

	if (argc != 5) {
		fprintf(stderr, "usage: ktrace TRACE.csv FERR_MM MIN_ROWS MIN_CIRCLE_ROWS\n");
		return 2;
	}
	ferr = atof(argv[2]);
	min_rows = atol(argv[3]);
	min_circle = atol(argv[4]);
	f = fopen(argv[1], "r");
	if (!f) {
		printf("KTEST FAIL stack: cannot open the trace %s\n", argv[1]);
		return 1;
	}
	if (!fgets(line, sizeof(line), f))
		line[0] = 0;
	line[strcspn(line, "\r\n")] = 0;
	snprintf(badmsg, sizeof(badmsg), "trace header is '%.200s', want " HEADER,
		 line);
	check(!strcmp(line, HEADER), "trace header is " HEADER, badmsg);

	while (fgets(line, sizeof(line), f)) {
		char *p = line, *end;
		double ang;

		for (i = 0; i < 9; i++) {
			v[i] = strtod(p, &end);
			if (end == p || (i < 8 && *end != ',') ||
			    (i == 8 && *end && *end != '\n' && *end != '\r'))
				break;
			p = end + 1;
		}
		if (i < 9) {
			bad++;
			continue;
		}
		t = v[0];
		if (rows > 0 && t <= lt)
			tback++;
		if (rows++ == 0)
			t0 = t;
		lt = t;

		d = dpath(v[1], v[3]);
		if (d > mcmd) {
			mcmd = d;
			mcmd_t = t;
		}
		d = dpath(v[2], v[4]);
		if (d > mact) {
			mact = d;
			mact_t = t;
		}
		d = hypot(v[1] - v[2], v[3] - v[4]);
		d = fmax(d, fmax(fabs(v[5] - v[6]), fabs(v[7] - v[8])));
		if (d > mferr) {
			mferr = d;
			mferr_t = t;
		}
		for (i = 5; i < 9; i++)
			mza = fmax(mza, fabs(v[i]));

		/* on the circle, clear of both lines, away from the junction */
		ang = atan2(v[3] - 5, v[1] - 10) * 180 / M_PI;
		if (dcircle(v[1], v[3]) < 0.1 &&
		    dseg(v[1], v[3], 0, 0, 10, 0) > 0.1 &&
		    dseg(v[1], v[3], 10, 0, 4, 3) > 0.1 && fabs(ang + 90) > 20) {
			ncirc++;
			mrc = fmax(mrc, dcircle(v[1], v[3]));
			mra = fmax(mra, dcircle(v[2], v[4]));
			oct[(int)((ang + 180) / 45) & 7] = 1;
		}
		memcpy(last, v, sizeof(last));
	}
	fclose(f);

	snprintf(good, sizeof(good),
		 "trace has %ld rows (>= %ld) of 9 numbers, time increasing (%.3f..%.3f s card time)",
		 rows, min_rows, t0, lt);
	snprintf(badmsg, sizeof(badmsg),
		 "trace has %ld rows (want >= %ld), %ld malformed, %ld with time not increasing",
		 rows, min_rows, bad, tback);
	check(!bad && rows >= min_rows && !tback, good, badmsg);
	if (!rows)
		return 1;

	snprintf(good, sizeof(good),
		 "set-point within %.3f mm of the programmed path (max %.4f mm)",
		 CMD_TOL, mcmd);
	snprintf(badmsg, sizeof(badmsg),
		 "set-point %.4f mm off the programmed path at t=%.4f s (limit %.3f mm)",
		 mcmd, mcmd_t, CMD_TOL);
	check(mcmd <= CMD_TOL, good, badmsg);

	snprintf(good, sizeof(good),
		 "encoder within %.3f mm of the programmed path (max %.4f mm)",
		 CMD_TOL + ferr, mact);
	snprintf(badmsg, sizeof(badmsg),
		 "encoder %.4f mm off the programmed path at t=%.4f s (limit %.3f mm)",
		 mact, mact_t, CMD_TOL + ferr);
	check(mact <= CMD_TOL + ferr, good, badmsg);

	snprintf(good, sizeof(good),
		 "following error <= %.4f mm in every row (max %.4f mm)",
		 ferr, mferr);
	snprintf(badmsg, sizeof(badmsg),
		 "following error %.4f mm at t=%.4f s (limit %.4f mm)",
		 mferr, mferr_t, ferr);
	check(mferr <= ferr, good, badmsg);

	snprintf(badmsg, sizeof(badmsg), "z or a moved by %.6f mm", mza);
	check(mza <= 1e-6, "z and a stay at 0", badmsg);

	for (i = 0; i < 8; i++)
		noct += oct[i];
	snprintf(good, sizeof(good),
		 "circle R5: %ld rows in all 8 octants, |r-R| set-point %.4f mm (<= %.3f), encoder %.4f mm (<= %.3f)",
		 ncirc, mrc, CIRC_TOL, mra, CIRC_TOL + ferr);
	snprintf(badmsg, sizeof(badmsg),
		 "circle R5: %ld rows (want >= %ld) in %d of 8 octants, |r-R| set-point %.4f mm (limit %.3f), encoder %.4f mm (limit %.3f)",
		 ncirc, min_circle, noct, mrc, CIRC_TOL, mra, CIRC_TOL + ferr);
	check(ncirc >= min_circle && noct == 8 && mrc <= CIRC_TOL &&
	      mra <= CIRC_TOL + ferr, good, badmsg);

	dc = hypot(last[1] - 4, last[3] - 3);
	da = hypot(last[2] - 4, last[4] - 3);
	snprintf(good, sizeof(good),
		 "ends at X4 Y3: set-point %.4f mm (<= %.4f), encoder %.4f mm (<= %.3f) away",
		 dc, END_CMD, da, END_ACT);
	snprintf(badmsg, sizeof(badmsg),
		 "last row set-point (%.4f, %.4f) is %.4f mm from X4 Y3 (limit %.4f), encoder %.4f mm (limit %.3f)",
		 last[1], last[3], dc, END_CMD, da, END_ACT);
	check(dc <= END_CMD && da <= END_ACT, good, badmsg);
	return g_failed ? 1 : 0;
}
