/* SPDX-License-Identifier: MIT */
/*
 * What the SH-2000 command-line tools (sh2000ctl, sh2000-upload,
 * sh2000-tune, sh2000-sim) share: the device option, one message format,
 * one set of exit codes, axis and number parsing, parameter lines, the
 * gnuplot runner. Static library `sh2000_toolcommon`.
 *
 * Messages go to stderr as "<tool>: <device>: <reason>", for example
 *     sh2000ctl: sim: axis 2 parameter kp: -1.5 is negative
 *     sh2000ctl: sim:shop: no card served at /sh2000-shop: ... (start sh2000-sim first)
 * Call sh2000_tool_init() first with the tool's name (the only state this
 * library keeps; a tool is one program, so that is not the library rule's
 * "global mutable state" of libsh2000).
 */
#ifndef SH2000_TOOLCOMMON_H
#define SH2000_TOOLCOMMON_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <sh2000/sh2000.h>

/*
 * Exit codes of every tool, one meaning per number (documented in each man
 * page and docs/tools.md). 0..4 can end any command; 5..8 end only what can
 * meet them. 5 keeps sh2000-upload's old "program has errors" and 7 the
 * "stopped" that sh2000-upload, sh2000ctl and sh2000-tune already shared;
 * sh2000-tune's abort on a protective limit, once 5, is 8, so that 5 means
 * one thing everywhere.
 */
enum sh2000_tool_exit {
	SH2000_EXIT_OK = 0,	/* done */
	SH2000_EXIT_CARD = 1,	/* the card or the library refused or failed
				 * (command error, timeout, bad value, I/O),
				 * an input file cannot be read, a parameter
				 * file has errors */
	SH2000_EXIT_USAGE = 2,	/* bad command line */
	SH2000_EXIT_DEVICE = 3,	/* the device cannot be opened */
	SH2000_EXIT_FAULT = 4,	/* a fault or emergency stop is latched */
	SH2000_EXIT_INPUT = 5,	/* an input file (a program, a tool table, a
				 * compensation table, a laser CSV) has
				 * errors in it: nothing moved, nothing
				 * changed on the card */
	SH2000_EXIT_HELPER = 6,	/* a helper program (rs274, gnuplot) is
				 * missing or failed */
	SH2000_EXIT_STOPPED = 7, /* stopped by the operator (SIGINT, SIGTERM)
				  * or by a STOP from another program: the
				  * card at rest, nothing latched */
	SH2000_EXIT_ABORTED = 8, /* a test aborted on a protective limit (the
				  * following-error bound): the card's fault
				  * cleared, the axis and parameters put
				  * back */
};

/*
 * --version of every tool: the tool, the library actually loaded (and its
 * SONAME), the protocol it speaks and the driver ABI it expects, e.g.
 *     sh2000ctl 0.1.0
 *     libsh2000 0.1.0 (libsh2000.so.0)
 *     protocol 1.0
 *     driver ABI 1
 */
void sh2000_tool_print_version(const char *tool_version);

/* Set the tool name used as the prefix of every message. */
void sh2000_tool_init(const char *name);
const char *sh2000_tool_name(void);

/* "<tool>: <fmt...>\n" on stderr. */
void sh2000_tool_msg(const char *fmt, ...)
	__attribute__((format(printf, 1, 2)));
void sh2000_tool_vmsg(const char *fmt, va_list ap);

/* A usage error: "<tool>: <fmt...>" and "Try '<tool> --help'." (or
 * "<tool> <sub> --help" when sub is not NULL) on stderr; returns
 * SH2000_EXIT_USAGE so callers can `return sh2000_tool_usage(...)`. */
int sh2000_tool_usage(const char *sub, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* The folder of output file PATH for option OPT writable (PATH NULL: no
 * output): 0, else a usage error naming both ("cannot write in DIR:
 * reason (nothing moved)"), SH2000_EXIT_USAGE. Checked before the card
 * is touched. outpath.c. */
int sh2000_tool_writable(const char *opt, const char *path);

/* The device string a tool uses: the -d/--device argument if not NULL or
 * empty, else $SH2000_DEVICE if set and not empty, else /dev/sh2000-0. */
const char *sh2000_tool_device(const char *arg);

/* Open the device (as sh2000_tool_device() resolves it). On failure prints
 * the library's message ("<tool>: <device>: <reason>") and returns
 * SH2000_EXIT_DEVICE; 0 on success. */
int sh2000_tool_open(struct sh2000 **h, const char *device_arg);

/* The exit code for a library error: SH2000_EXIT_FAULT for latched faults
 * and emergency stop (-SH2000_EESTOP..-SH2000_ESKEW, ECMD_FAULTED),
 * SH2000_EXIT_CARD for every other negative code, 0 for code >= 0. */
int sh2000_tool_exit_code(int code);

/* Report a failed library call on h on stderr as
 * "<tool>: <device>: <what>: <reason>", the reason being
 * sh2000_last_error(h) (without its leading device) when set, else
 * sh2000_strerror(code). what may be NULL. Returns
 * sh2000_tool_exit_code(code). */
int sh2000_tool_fail(struct sh2000 *h, int code, const char *what);

/* Axis names: "x" "y" "z" "a" (any case) or "0".."3" -> 0..3; -1 else. */
int sh2000_tool_axis(const char *s);
/* "x", "x,y", "xyz", "all" -> mask of bits 0..3; -1 if any part is bad. */
int sh2000_tool_axes(const char *s);
/* Lower-case letter of axis 0..3 ('?' otherwise). */
char sh2000_tool_axis_name(unsigned int axis);

/* Whole string is a finite number / an integer in [min, max]: 0, else -1. */
int sh2000_tool_double(const char *s, double *v);
int sh2000_tool_long(const char *s, long min, long max, long *v);

/* Write text[0..len) to path ("-": stdout), as the last step of a command
 * that built it in memory first (so a card that fails half-way costs no
 * file). "<tool>: <path>: cannot create/write error" on failure, and a
 * half-written file is removed. Returns an exit code. */
int sh2000_tool_write_text(const char *path, const char *text, size_t len);

/* Parameter files (paramfile.c; the format is sh2000ctl's, see
 * tools/ctl/params_plan.h): a shortest text of parameter id's value v
 * that reads back as v (as the same float for a binary32 one), and the
 * line "name = value   # unit". */
void sh2000_tool_param_format(char *buf, size_t len, unsigned int id,
			      double v);
void sh2000_tool_param_line(FILE *f, unsigned int id, double v);

/* Pictures through gnuplot (gnuplot.c, Debian package gnuplot-nox). */
struct sh2000_tool_plot_kind {
	int svg;	/* the output is SVG (its name ends in .svg) */
	int cairo;	/* PNG through pngcairo, else libgd's png */
};
/* Writes a picture's script into f for out: 0 or -errno. */
typedef int (*sh2000_tool_plot_script)(FILE *f, const void *ctx,
				       const char *out,
				       const struct sh2000_tool_plot_kind *k);

/* Draw out (SVG if its name ends in .svg, else PNG: pngcairo, then libgd's
 * png if this gnuplot lacks cairo) with the script write_script(ctx)
 * writes, gnuplot's DATA set to the data file. The script and gnuplot's
 * stderr go to dir and are removed after. An exit code, the message
 * printed: 0; SH2000_EXIT_HELPER when gnuplot is missing ("gnuplot not
 * found on PATH") or fails (its stderr shown); SH2000_EXIT_CARD when the
 * script cannot be written. */
int sh2000_tool_plot(const char *dir, const char *data, const char *out,
		     sh2000_tool_plot_script write_script, const void *ctx);

/* The lines every picture's script starts with: the terminal of kind k at
 * width x height pixels, the output, a grid and the multiplot's title. */
void sh2000_tool_plot_head(FILE *f, const char *out, const char *title,
			   const struct sh2000_tool_plot_kind *k,
			   unsigned int width, unsigned int height);

/* s as a gnuplot single-quoted string (a quote inside becomes '_'). */
void sh2000_tool_gnuplot_quoted(FILE *f, const char *s);

/* SIGINT and SIGTERM (stopsignal.c): the operator asks the tool to stop.
 * sh2000_tool_catch_stop() installs the one handler and sets the count to
 * 0; sh2000_tool_stop_asked() is the number of signals since, at most 2.
 * SH2000_SECOND_COUNTS: a second signal counts (sh2000-upload makes it an
 * emergency stop); SH2000_SECOND_KILLS: a second signal has the default
 * action and ends the program at once. */
enum sh2000_tool_second { SH2000_SECOND_COUNTS, SH2000_SECOND_KILLS };
void sh2000_tool_catch_stop(enum sh2000_tool_second second);
int sh2000_tool_stop_asked(void);

#endif /* SH2000_TOOLCOMMON_H */
