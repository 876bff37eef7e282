/* SPDX-License-Identifier: MIT */
/* Shared by the readers: the reading context, diagnostics, blocks, arcs. */
#ifndef SH2000_PROG_INTERNAL_H
#define SH2000_PROG_INTERNAL_H

#include <stdarg.h>

#include "sh2000/program.h"

#define PROG_MM_PER_INCH 25.4

/* Warning kinds given once per program. */
enum prog_warn_kind {
	PW_SPINDLE = 1u << 0,	/* M3 M4 M5 */
	PW_SPEED = 1u << 1,	/* S */
	PW_TOOL = 1u << 2,	/* T */
	PW_TOOLCHANGE = 1u << 3,/* M6 */
	PW_COOLANT = 1u << 4,	/* M7 M8 M9 */
	PW_PATHMODE = 1u << 5,	/* G61 G61.1 G64 */
	PW_MESSAGE = 1u << 6,	/* (MSG,...) and friends */
	PW_AFTER_END = 1u << 7,	/* text after M2/M30 or % */
	PW_UNITS_F = 1u << 8,	/* F next to a units change */
	PW_A_INCH = 1u << 9,	/* A under G20 */
	PW_TLO_UNITS = 1u << 10,/* an offset changed in other units */
};

struct prog_ctx {
	struct sh2000_program *prog;	/* where blocks go */
	struct sh2000_prog_diags *diags;
	struct sh2000_prog_options opt;
	const char *name;
	unsigned int errors;	/* in this read */
	bool stop;		/* error limit reached */
	bool oom;
	unsigned int warned;	/* enum prog_warn_kind bits */
	double pos[SH2000_AXES];
	bool replay;		/* a second pass: warnings were given */
	bool quiet;		/* a scan (sh2000_prog_reader_axes): no
				 * diagnostics at all */
};

/* Append a diagnostic; returns -SH2000_PROG_EINVALID for an error, 0 for
 * a warning (or -ENOMEM). Errors past max_errors set ctx->stop. */
int prog_diag(struct prog_ctx *c, enum sh2000_prog_severity sev,
	      enum sh2000_prog_diag_code code, unsigned int line,
	      unsigned int col, const char *fmt, ...)
	__attribute__((format(printf, 6, 7)));
#define prog_err(c, code, line, col, ...) \
	prog_diag((c), SH2000_PROG_ERROR, (code), (line), (col), __VA_ARGS__)
/* A warning of this kind unless one was given already. */
int prog_warn_once(struct prog_ctx *c, unsigned int kind,
		   enum sh2000_prog_diag_code code, unsigned int line,
		   unsigned int col, const char *fmt, ...)
	__attribute__((format(printf, 6, 7)));

/* The tool state of a program being read (toolstate.c): the tool its
 * last T word selected, the one its last tool change put in the spindle
 * (0: none, as LinuxCNC starts) and the tool length offset in force, mm
 * for X Y Z A: a position the program names for the tool's tip is the
 * machine's position minus it. */
struct prog_tool_state {
	int selected, loaded;
	double offset[SH2000_AXES];
};

/* T n (or SELECT_TOOL): n an integer >= 0 and, with a tool
 * table, in it; reported once. 0 or an error. */
int prog_tool_select(struct prog_ctx *c, struct prog_tool_state *t,
		     double n, unsigned int line, unsigned int col);
/* A tool change to the selected tool (what: "M6" or the command): a PAUSE
 * block when the options ask for one, else reported once. */
int prog_tool_change(struct prog_ctx *c, struct prog_tool_state *t,
		     const char *what, unsigned int line, unsigned int col);
/* The offsets of tool n in the table (tool 0: none) into out, or an
 * error naming what asked ("G43 H2"). */
int prog_tool_offsets(struct prog_ctx *c, int n, double out[SH2000_AXES],
		      const char *what, unsigned int line, unsigned int col);

/* Free the blocks' curves and empty the list (its memory stays). */
void prog_clear_blocks(struct sh2000_program *p);
/* Every block of reader r into prog (reader.c). */
int prog_read_all(struct sh2000_prog_reader *r, struct sh2000_program *prog);

/* A new block at the end of the program with start = end = ctx->pos; NULL
 * when out of memory (ctx->oom set). */
struct sh2000_prog_block *prog_push(struct prog_ctx *c,
				    enum sh2000_prog_kind kind,
				    unsigned int line, unsigned int col);

/* Fill b->u.arc of an ARC block whose start and end are set, from the
 * centre (c1, c2) in the plane's (axis1, axis2) coordinates; checks the
 * radii against tol_mm (absolute) and the relative tolerance. An end
 * closer than same_mm to the start (in the plane) makes a full circle. */
int prog_arc_fill(struct prog_ctx *c, struct sh2000_prog_block *b,
		  enum sh2000_plane plane, double c1, double c2,
		  bool ccw, unsigned int turns, double tol_mm, double same_mm,
		  unsigned int line, unsigned int col);

/* Centre of an R-format arc (LinuxCNC arc_data_r); 0 or an error. */
int prog_arc_centre_r(struct prog_ctx *c, double s1, double s2, double e1,
		      double e2, double r, bool ccw, double *c1, double *c2,
		      unsigned int line, unsigned int col);

/* A NURBS being read: arrays the reader fills. A block's u.nurbs becomes a
 * const view of them (prog_nurbs_give) and the program frees them. */
struct prog_nurbs_buf {
	unsigned int degree;
	size_t npoints;
	double (*points)[SH2000_AXES];
	double *weights;
	double *knots;		/* npoints + degree + 1 */
};

/* Zeroed arrays for np points of a degree-deg curve; -ENOMEM (ctx->oom
 * set) when out of memory, nothing left allocated. */
int prog_nurbs_alloc(struct prog_ctx *c, struct prog_nurbs_buf *n,
		     unsigned int deg, size_t np);
void prog_nurbs_free(struct prog_nurbs_buf *n);
/* The const view for checks and evaluation. */
struct sh2000_nurbs prog_nurbs_view(const struct prog_nurbs_buf *n);
/* Hand the arrays to block b (which then owns them); n is emptied. */
void prog_nurbs_give(struct prog_nurbs_buf *n, struct sh2000_prog_block *b);

/* Validate a NURBS (degree, counts, knots, weights); field names the
 * source ("knots" ...) in messages. 0 or an error. */
int prog_nurbs_check(struct prog_ctx *c, const struct sh2000_nurbs *n,
		     unsigned int line, unsigned int col);

/*
 * A reader of one format, fed line by line (reader.c drives it): init
 * before the first line, line for each (without its end, numbered from 1),
 * finish after the last (with the last line's number), release at the end
 * or before a rewind. Blocks go to ctx->prog with prog_push(); ctx->stop
 * ends the reading early.
 */
struct prog_format_ops {
	size_t state_size;
	void (*init)(struct prog_ctx *c, void *state);
	void (*line)(struct prog_ctx *c, void *state, const char *s, size_t n,
		     unsigned int line);
	void (*finish)(struct prog_ctx *c, void *state, unsigned int line);
	void (*release)(void *state);	/* may be NULL */
};

extern const struct prog_format_ops prog_gcode_ops;
extern const struct prog_format_ops prog_canon_ops;
extern const struct prog_format_ops prog_csv_ops;
extern const struct prog_format_ops prog_json_ops;

#endif
