/* SPDX-License-Identifier: MIT */
/*
 * Calibration of the compensation tables (docs/compensation.md): the
 * tables as lists of corrections in mm, written as a table file; the
 * simulated machine (in-process `sim`) moved over lines and a grid while
 * its interferometer is read; a laser system's CSV turned into a table.
 * Shared by sh2000-comp, its benchmark (bench/comp) and tests (tests/comp).
 */
#ifndef SH2000_COMP_CALIB_H
#define SH2000_COMP_CALIB_H

#include <stdio.h>

#include "sh2000/sh2000.h"
#include "sh2000/sim.h"

#define CAL_MAX_POINTS	4096u
#define CAL_MAX_GRID	64u

/* One correction curve: positions (mm, nominal) and corrections (mm). */
struct cal_line {
	unsigned int n;
	double pos[CAL_MAX_POINTS], corr[CAL_MAX_POINTS];
};

/* What a calibration finds, in the order the card applies it (all added
 * to the nominal set-point): each axis' pitch, Y's straightness along X,
 * X's along Y with the X-Y squareness split off, Z's flatness over X-Y. */
struct cal_tables {
	struct cal_line pitch[SH2000_AXES];
	struct cal_line cross_yx;	/* Y corrected by X's position */
	struct cal_line cross_xy;	/* X by Y's, squareness taken out */
	double square_xy;		/* X += square_xy * Y (mm/mm) */
	unsigned int gn1, gn2;		/* Z by X (n1) and Y (n2); 0: none */
	double gu0, gdu, gv0, gdv;
	double grid[CAL_MAX_GRID * CAL_MAX_GRID];
	/* the raw X-by-Y corrections (square and cross together) */
	struct cal_line raw_xy;
};

/* The table file (sh2000ctl comp load); 0 or -errno. */
int cal_tables_write(const struct cal_tables *t, FILE *f, const char *comment);
int cal_tables_save(const struct cal_tables *t, const char *path,
		    const char *comment);

/* A curve from a laser system's CSV, in mm: rows "nominal,measured"
 * (pitch: the correction is nominal - measured) or, cross != 0,
 * "nominal,deviation" of another axis (straightness: the correction is
 * -deviation); relative to the first row, one point more beyond each end.
 * Only the CSV's own form is checked here (two whole finite numbers a row,
 * 2 rows or more); whether the table is one the card takes is
 * cal_csv_check's. lines (CAL_MAX_POINTS, may be NULL): each row's line,
 * before the end points are added. 0, or -1 with "FILE:LINE: why" in msg,
 * or -errno with "FILE: why" when the file cannot be read. */
int cal_from_csv(struct cal_line *out, unsigned int *lines, const char *path,
		 int cross, char *msg, size_t len);

/* The table t made by cal_from_csv from csv (rows: its points, lines:
 * their lines) read and checked by the library as `sh2000ctl comp load`
 * does on the card h (its scales and limits), before anything is written:
 * 0; -SH2000_EPARAM with "CSV:LINE: why" in msg, the line of the row the
 * faulty point came from; another negative code when the check could not
 * run. A table the card takes is judged against the card's soft limits
 * too (sh2000_comp_reach_file()): warn (may be NULL) gets the library's
 * words for each soft limit it moves the tool beyond. */
int cal_csv_check(const struct cal_tables *t, const unsigned int *lines,
		  unsigned int rows, const char *csv, struct sh2000 *h,
		  void (*warn)(const char *words), char *msg, size_t len);

/* ---- the simulated machine ---- */

struct cal_config {
	double lo[SH2000_AXES], hi[SH2000_AXES];	/* travel, mm */
	double step_mm;		/* lines' spacing (1) */
	double grid_mm;		/* the flatness grid's (25) */
	double feed;		/* mm/s between points (50) */
	unsigned int passes;	/* measure again with the tables on (2) */
	int verbose;
};

void cal_config_default(struct cal_config *c);

struct cal_sim {
	struct sh2000 *h;
	struct sh2000_fw *fw;
	double scale[SH2000_AXES];
	double ref_nom[SH2000_AXES], ref_tool[SH2000_AXES];
	double ref_sp[SH2000_AXES];	/* counts: the corrected set-point
					 * the reference was taken at */
	double at[SH2000_AXES];		/* the last target, mm */
	struct sh2000_geometry geom;	/* the machine's, for the path's
					 * breakdown (pathmodel.c) */
	const char *tmp;		/* where tables go before a load */
};

/* Open `sim` (cfg NULL: the default plants) with geometry g (NULL: the
 * default machine's errors, sh2000_geometry_default()), enable every axis
 * and take the reference (the interferometer zeroed where the machine
 * stands, under a half-count table, centred on the count: cal_reference();
 * no tables are loaded after). */
int cal_sim_open(struct cal_sim *s, const struct sh2000_sim_config *cfg,
		 const struct sh2000_geometry *g, const char *tmp, char *msg,
		 size_t len);
void cal_sim_close(struct cal_sim *s);
int cal_move(struct cal_sim *s, const double target[SH2000_AXES], double feed);
/* At rest: the error (mm) of the tool against the nominal target, both
 * from the reference; averaged over a few ms. */
int cal_measure(struct cal_sim *s, double err[SH2000_AXES]);
/* Load tables (through a file, as a user would) and wait for the switch. */
int cal_load(struct cal_sim *s, const struct cal_tables *t);
int cal_wait_switch(struct cal_sim *s);
/* The tool averaged at rest (mm, machine frame). */
int cal_tool_avg(struct cal_sim *s, double tool[SH2000_AXES]);
/* Centring on the counter's count (calcentre.c): a table of half a count
 * on every axis; the reference taken under it; the error at rest, where
 * the card's loop holds the reading, in the middle of the corrected
 * set-point's count (*loose, the axes whose measurement could not be
 * used, is none). */
void cal_half_count(struct cal_tables *t, const struct cal_sim *s);
int cal_reference(struct cal_sim *s);
int cal_measure_centred(struct cal_sim *s, double err[SH2000_AXES],
			unsigned int *loose);
/* The whole calibration: passes over lines and the grid. */
int cal_run(struct cal_sim *s, const struct cal_config *c,
	    struct cal_tables *t);

/* A program's path on the machine (pathcheck.c): a star of straight moves
 * in X-Y-Z within +-0.9 half mm of the reference, each point reached at
 * rest. Distances in mm over X, Y, Z; "largest" over every servo cycle. */
struct cal_path {
	/* what the user sees: the tool (interferometer) against the
	 * programmed path's exact geometry (its segments) */
	double path_max, path_rms;
	/* the same square to the segment's line: the contour error, the
	 * along-path lead or lag (and a corner's overshoot) left out */
	double contour_max, contour_rms;
	double contour_axis_max;	/* its largest part along one axis */
	unsigned long contour_over;	/* cycles with it over one count (the
					 * largest of X's, Y's and Z's) */
	double rest_max;		/* tool against the program's points,
					 * at rest (averaged) */
	/* the path the corrected set-points describe: the tool a perfect
	 * servo on an unquantised scale would give, against the segments
	 * (the planner's and the tables' parts together, the servo's out) */
	double setpoint_max;
	/* what it is made of (each largest over the run) */
	double plan_max;		/* the nominal set-point off the path */
	double table_max;		/* the tables: the tool a perfect servo
					 * on an unquantised scale would give
					 * for the corrected set-point, against
					 * the nominal one */
	double servo_perp_max;		/* moving: the tool against that, square
					 * to the path (the servo's lag leaving
					 * the path) */
	double quant_max;		/* at rest: the same, the dither within
					 * the counter's count */
	/* a different question: the tool against the position the card
	 * reports (its counter, nominal): what a user comparing the laser
	 * with ACT sees; includes the counter's count and the rounding of
	 * the correction to counts */
	double geo_max, geo_rms;
	double lag_max;			/* counts: the servo's following error */
	double vel_ratio;		/* corrected set-point velocity / vmax */
	double acc_ratio;		/* its acceleration / amax */
	unsigned long outside;		/* cycles with a set-point outside the
					 * axis' soft limits */
	unsigned long cycles;
};

/* The model (pathmodel.c). */
void cal_model_carriage(const struct sh2000_geometry *g,
			const double tool[SH2000_AXES], double x[SH2000_AXES]);
void cal_model_offset(const struct cal_sim *s, const double counter[SH2000_AXES],
		      const double tool[SH2000_AXES], double k[SH2000_AXES]);
void cal_model_tool(const struct cal_sim *s, const double k[SH2000_AXES],
		    const double sp[SH2000_AXES], double tool[SH2000_AXES]);
double cal_model_segment(const double a[3], const double b[3],
			 const double p[3], const double d[3], double perp[3]);

int cal_path_check(struct cal_sim *s, double half, struct cal_path *out);

#endif /* SH2000_COMP_CALIB_H */
