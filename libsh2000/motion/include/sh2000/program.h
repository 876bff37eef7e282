/* SPDX-License-Identifier: MIT */
/*
 * Program readers of libsh2000-motion: RS-274 G-code (built-in parser),
 * LinuxCNC rs274 canonical-command output, CSV point lists and JSON NURBS
 * files, all read into one device- and planner-independent representation
 * (docs/programs.md describes the accepted input).
 *
 * A program is an array of blocks. Every motion block carries its absolute
 * start and end points in mm for the four axes X Y Z A (A is the card's
 * fourth *linear* axis, written "A" in every format and always in mm: G20
 * does not scale it, as LinuxCNC never scales A), its feed in mm/s and
 * its source position, so a consumer needs no modal state: units, distance
 * modes and relative arc centres are resolved by the reader.
 *
 * A reader checks the whole input before it returns: on any error the
 * program is left empty, every error and warning is in the caller's
 * diagnostics list with file:line:column, and the call returns
 * -SH2000_EPROGRAM (alias SH2000_PROG_EINVALID). Nothing here has global
 * mutable state.
 *
 * Errors: negative codes, -errno for system errors (reading a file, memory)
 * or -SH2000_EPROGRAM / -SH2000_EFORMAT; sh2000_strerror() names them.
 */
#ifndef SH2000_PROGRAM_H
#define SH2000_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include "sh2000/geometry.h"
#include "sh2000/path.h"
#include "sh2000/sh2000.h"

#ifdef __cplusplus
extern "C" {
#endif

enum sh2000_prog_axis {
	SH2000_PROG_X = 0,
	SH2000_PROG_Y = 1,
	SH2000_PROG_Z = 2,
	SH2000_PROG_A = 3,	/* the fourth linear axis, mm */
};

/* The readers' codes are libsh2000's (one error space, one
 * sh2000_strerror()); the functions return them negated. */
enum sh2000_prog_error {
	SH2000_PROG_EINVALID = SH2000_EPROGRAM,	/* the program has errors
						   (see diags) */
	SH2000_PROG_EFORMAT = SH2000_EFORMAT,	/* format unknown (name
						   gives no hint) */
};

/* Same as sh2000_strerror() (kept for programs written against it). */
const char *sh2000_prog_strerror(int code);

/* ---- source positions and diagnostics -------------------------------- */

/* line and column count from 1 (line 0: the file as a whole, e.g. it
 * cannot be read); column is a byte column (a tab is one). */
struct sh2000_prog_pos {
	const char *file;	/* owned by the program (or diags list) */
	unsigned int line;
	unsigned int column;
};

enum sh2000_prog_severity {
	SH2000_PROG_WARNING = 0,
	SH2000_PROG_ERROR = 1,
};

/* What a diagnostic is about; tests and tools may switch on it. */
enum sh2000_prog_diag_code {
	SH2000_PD_SYNTAX = 1,	/* malformed word, number, comment, line */
	SH2000_PD_UNKNOWN,	/* no such word, G or M code, command, field */
	SH2000_PD_UNSUPPORTED,	/* valid RS274NGC/LinuxCNC, not in this subset */
	SH2000_PD_NO_AXIS,	/* an axis this card does not have (B C U V W) */
	SH2000_PD_CONFLICT,	/* same modal group twice, repeated word */
	SH2000_PD_MISSING,	/* a required word or field is missing */
	SH2000_PD_RANGE,	/* value out of range, NaN, inf, not integer */
	SH2000_PD_ARC,		/* arc geometry (radii differ, cannot reach) */
	SH2000_PD_FEED,		/* feed move without a positive feed rate */
	SH2000_PD_NURBS,	/* NURBS structure (points, order, knots) */
	SH2000_PD_NOT_ACTED,	/* warning: accepted, not acted on (S, M3...) */
	SH2000_PD_IGNORED,	/* warning: text after the end, messages */
	SH2000_PD_LIMIT,	/* too many errors: reading stopped */
	SH2000_PD_ORDER,	/* warning: read as LinuxCNC does, which may
				 * not be what the line seems to say */
	SH2000_PD_TOOL,		/* a tool not in the tool table (or none) */
};

struct sh2000_prog_diag {
	enum sh2000_prog_severity severity;
	enum sh2000_prog_diag_code code;
	struct sh2000_prog_pos pos;	/* pos.file owned by the list */
	char *message;
};

/* The caller's list; readers append to it. */
struct sh2000_prog_diags {
	struct sh2000_prog_diag *items;
	size_t count, cap;
	size_t errors, warnings;
};

void sh2000_prog_diags_init(struct sh2000_prog_diags *d);
void sh2000_prog_diags_free(struct sh2000_prog_diags *d);
/* "file:line:column: error: message" into buf; returns snprintf's length. */
int sh2000_prog_diag_format(const struct sh2000_prog_diag *g, char *buf,
			    size_t size);
/* Every diagnostic, one a line, in that form; returns the count printed
 * or -errno. f is a FILE *, void here to keep stdio out of this header. */
int sh2000_prog_diags_print(const struct sh2000_prog_diags *d, void *f);

/* ---- blocks ----------------------------------------------------------- */

enum sh2000_prog_kind {
	SH2000_PROG_RAPID = 1,	/* G0: straight, at the rapid rate */
	SH2000_PROG_LINE,	/* G1: straight, at feed */
	SH2000_PROG_ARC,	/* G2/G3: circle or helix, at feed */
	SH2000_PROG_NURBS,	/* G5.2/G5.3, JSON NURBS: at feed */
	SH2000_PROG_FEED,	/* the feed rate changes (F) */
	SH2000_PROG_DWELL,	/* G4 P: wait */
	SH2000_PROG_PAUSE,	/* M0/M1 (or a tool change, when asked):
				 * stop until the operator resumes */
	SH2000_PROG_END,	/* M2/M30 */
	SH2000_PROG_PATH_MODE,	/* G61, G61.1, G64 [P [Q]] */
};

/*
 * An ARC block's u.arc is geometry.h's struct sh2000_arc (plane, centre and
 * the true circle through both ends in plane coordinates, radii, sweep,
 * turns as P), a NURBS block's u.nurbs its struct sh2000_nurbs (the arrays
 * belong to the program). The block's start and end complete them.
 */

struct sh2000_prog_block {
	enum sh2000_prog_kind kind;
	struct sh2000_prog_pos pos;
	/* Motion: absolute start and end, mm. Others: both the position. */
	double start[SH2000_AXES];
	double end[SH2000_AXES];
	/* LINE, ARC, NURBS: the feed in mm/s; FEED: the new feed in mm/s;
	 * RAPID and the others: 0. */
	double feed;
	union {
		struct sh2000_arc arc;		/* ARC */
		struct sh2000_nurbs nurbs;	/* NURBS */
		double feed_mm_min;	/* FEED: as programmed, in mm/min */
		double dwell_s;		/* DWELL: seconds */
		bool optional;		/* PAUSE: M1 (optional stop) */
		int end_code;		/* END: 2 (M2) or 30 (M30) */
		struct {		/* PATH_MODE, for sh2000_path_set_mode */
			enum sh2000_path_mode mode;
			double tolerance;	/* P in mm; 0: none given */
			double naive_tolerance;	/* Q in mm (P without Q) */
		} path;
	} u;
	/* PAUSE made by a tool change (M6, rs274's CHANGE_TOOL) when the
	 * reader's options ask to pause there: tool_change set and tool the
	 * tool to put in the spindle (0: none). Otherwise both 0. */
	bool tool_change;
	int tool;
};

struct sh2000_program {
	char *file;			/* the name positions point to */
	struct sh2000_prog_block *blocks;
	size_t count, cap;
};

void sh2000_program_init(struct sh2000_program *p);
void sh2000_program_free(struct sh2000_program *p);

/* ---- tool tables ------------------------------------------------------- */

/*
 * A tool table in LinuxCNC's format, one tool a line:
 *
 *     T1 P1 Z+10.0 D6.0 ;comment
 *
 * T the tool number (>= 1), P the pocket (required), X Y Z A the tool's
 * offsets, D its diameter, I J its front and back angles and Q its
 * orientation (lathe tools; kept, not used); ';' starts a comment. Lengths
 * are in machine units, as LinuxCNC reads its table: mm on an SH-2000
 * machine, whatever G20/G21 the program selects (docs/programs.md).
 */
struct sh2000_tool {
	int number;			/* T */
	int pocket;			/* P */
	double offset[SH2000_AXES];	/* X Y Z A, mm */
	double diameter;		/* D, mm */
	double front_angle, back_angle;	/* I J, degrees */
	int orientation;		/* Q */
	unsigned int line;		/* in the table's file */
	char *comment;			/* after ';', blanks trimmed; NULL: none */
};

struct sh2000_tool_table {
	char *file;			/* the name messages use */
	struct sh2000_tool *tools;	/* in the file's order */
	size_t count, cap;
};

void sh2000_tool_table_init(struct sh2000_tool_table *t);
void sh2000_tool_table_free(struct sh2000_tool_table *t);
/*
 * Read a table (text of len bytes named name) into t, which must be
 * initialised and is replaced. Every bad line is an error in diags with
 * name:line:column (a table line LinuxCNC would skip is refused here: a
 * tool left out would run with no offset). Returns 0,
 * -SH2000_PROG_EINVALID (errors in diags, t empty) or -ENOMEM.
 */
int sh2000_tool_table_read(struct sh2000_tool_table *t, const char *name,
			   const char *text, size_t len,
			   struct sh2000_prog_diags *diags);
/* The same from a file: -errno and an error naming it if unreadable. */
int sh2000_tool_table_read_file(struct sh2000_tool_table *t, const char *path,
				struct sh2000_prog_diags *diags);
/* Tool number n, or NULL. */
const struct sh2000_tool *
sh2000_tool_table_find(const struct sh2000_tool_table *t, int n);

/* ---- reading ------------------------------------------------------------ */

enum sh2000_prog_format {
	SH2000_PROG_AUTO = 0,	/* from the file name's extension */
	SH2000_PROG_GCODE,	/* .ngc .nc .gcode .g .tap .cnc */
	SH2000_PROG_CANON,	/* .canon: rs274 canonical-command output */
	SH2000_PROG_CSV,	/* .csv */
	SH2000_PROG_NURBS_JSON,	/* .json */
};

struct sh2000_prog_options {
	/* Where the machine is when the program starts, mm. G-code moves
	 * and arcs start there, CSV and JSON files rapid from there. */
	double start[SH2000_AXES];
	/* Feed in mm/s for CSV files without a feed column and JSON curves
	 * without "feed"; 0: none (a feed move without one is an error). */
	double feed_mm_s;
	/* Allowed difference of an arc's start and end radius in mm;
	 * 0: LinuxCNC's default for the active units (docs/programs.md). */
	double arc_tolerance_mm;
	/* Stop reading after this many errors; 0: 20. */
	unsigned int max_errors;
	/* The tool table G-code's T words are checked against and G43 and
	 * G43.2 take offsets from; NULL: none (T and M6 are then only
	 * reported, and an offset of a tool other than 0 is an error). Not
	 * copied: it must outlive the reader. */
	const struct sh2000_tool_table *tools;
	/* A tool change (M6, CHANGE_TOOL) becomes a PAUSE block with
	 * tool_change set; otherwise it is reported once. */
	bool pause_at_tool_change;
	uint64_t reserved[8];	/* room to grow, zero (sh2000.h, above
				 * struct sh2000_status) */
};

void sh2000_prog_options_default(struct sh2000_prog_options *o);

/* SH2000_PROG_AUTO when the name has no known extension. */
enum sh2000_prog_format sh2000_prog_format_guess(const char *name);
const char *sh2000_prog_format_name(enum sh2000_prog_format f);

/*
 * Read text (len bytes, no terminator needed) named name (positions and
 * messages use it) into prog, which must be initialised and is replaced.
 * opt NULL: defaults. Returns 0 (warnings may be in diags),
 * -SH2000_PROG_EINVALID (errors in diags, prog empty),
 * -SH2000_PROG_EFORMAT (AUTO and the name says nothing) or -ENOMEM.
 */
int sh2000_program_read(struct sh2000_program *prog,
			enum sh2000_prog_format fmt, const char *name,
			const char *text, size_t len,
			const struct sh2000_prog_options *opt,
			struct sh2000_prog_diags *diags);

/* The same from a file; "-" is standard input (named "<stdin>"). A file
 * that cannot be read gives -errno and an error naming the file. */
int sh2000_program_read_file(struct sh2000_program *prog,
			     enum sh2000_prog_format fmt, const char *path,
			     const struct sh2000_prog_options *opt,
			     struct sh2000_prog_diags *diags);

/* ---- reading block by block, in constant memory ------------------------- */

/*
 * A reader hands out a program's blocks one at a time, holding only the
 * current line's: a program of any length is read, checked and run in the
 * same memory (JSON NURBS files excepted: they are parsed whole). It can
 * be rewound for a second pass, the usual way being a first pass that
 * checks and plans everything and a second that streams it to the card.
 * Standard input ("-") is spooled to a temporary file for that.
 *
 * Errors and warnings go to diags (which must outlive the reader) as the
 * lines are read; reading goes on after an error to find more, up to
 * max_errors. After a rewind warnings are not given again, and an error
 * (the file changed since) makes next() fail.
 */
struct sh2000_prog_reader;

/* 0; -errno (the file cannot be read: an error in diags too),
 * -SH2000_PROG_EFORMAT or -SH2000_PROG_EINVALID (bad options); *out is
 * NULL on failure. */
int sh2000_prog_reader_open(struct sh2000_prog_reader **out,
			    enum sh2000_prog_format fmt, const char *path,
			    const struct sh2000_prog_options *opt,
			    struct sh2000_prog_diags *diags);
/* The same over text in memory (not copied: it must outlive the reader). */
int sh2000_prog_reader_open_text(struct sh2000_prog_reader **out,
				 enum sh2000_prog_format fmt, const char *name,
				 const char *text, size_t len,
				 const struct sh2000_prog_options *opt,
				 struct sh2000_prog_diags *diags);
/*
 * The next block: 1 and *b (valid until the next call), 0 at the end of
 * the program (or where reading stopped at max_errors), -ENOMEM or -EIO,
 * or -SH2000_PROG_EINVALID for an error found after a rewind.
 */
int sh2000_prog_reader_next(struct sh2000_prog_reader *r,
			    const struct sh2000_prog_block **b);
/* Back to the first block (the machine at opt->start again). */
int sh2000_prog_reader_rewind(struct sh2000_prog_reader *r);
/*
 * The axes the program moves: reads it from its first line to its end
 * without a diagnostic, and leaves the reader at its first line: one
 * nothing was read from yet as it was (its next read gives every warning
 * and error, as just opened), another as after a rewind. Bit a of *moves
 * is set when some block moves
 * axis a away from at[a], where it stands until then
 * (sh2000_prog_block_axes()). 0, -ENOMEM or -EIO; a program with errors
 * gives the axes of what could be read (the next read reports them).
 */
int sh2000_prog_reader_axes(struct sh2000_prog_reader *r,
			    const double at[SH2000_AXES], unsigned int *moves);
/* Errors found since the last open or rewind. */
unsigned int sh2000_prog_reader_errors(const struct sh2000_prog_reader *r);
/* The number of the line read last. */
unsigned int sh2000_prog_reader_line(const struct sh2000_prog_reader *r);
void sh2000_prog_reader_close(struct sh2000_prog_reader *r);

/* ---- geometry helpers for consumers and tests ---------------------------- */

/* Point at fraction s (0..1) of a LINE, RAPID, ARC or NURBS block (NURBS:
 * of the parameter range, not of the length). 0, or -EINVAL otherwise. */
int sh2000_prog_block_point(const struct sh2000_prog_block *b, double s,
			    double out[SH2000_AXES]);

const char *sh2000_prog_kind_name(enum sh2000_prog_kind k);

/* ---- planning a program --------------------------------------------------- */

/* Add one block to a planner: RAPID as a point-to-point move, LINE, ARC
 * and NURBS as path primitives, PATH_MODE as sh2000_path_set_mode(); the
 * other kinds add nothing (the caller acts on FEED, DWELL, PAUSE and END).
 * 0 or the planner's negative error (sh2000_path_error() has the words). */
int sh2000_path_add_block(struct sh2000_path *p,
			  const struct sh2000_prog_block *b);

/* The axes block b moves of those that stand at at[] before it: every
 * axis whose end differs from it, both axes of an arc's plane, every axis
 * a control point of a NURBS leaves. The planner refuses a block that moves
 * a still axis (sh2000_path_config.still_axes) by the same rule. */
unsigned int sh2000_prog_block_axes(const struct sh2000_prog_block *b,
				    const double at[SH2000_AXES]);

/* "file:line:column" of block b into buf; snprintf's return. */
int sh2000_prog_block_where(const struct sh2000_prog_block *b, char *buf,
			    size_t len);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_PROGRAM_H */
