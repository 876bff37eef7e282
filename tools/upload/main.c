// SPDX-License-Identifier: MIT
/*
 * sh2000-upload: run an NC program on an SH-2000TH card.
 *
 * The order of things (sh2000-upload(1) is the manual): read and check the
 * whole program, plan all of it once through a planner whose sink only
 * checks (limits, counts), and only then enable axes and stream the same
 * plan to the card with sh2000_run_*. An error before streaming leaves the
 * card as it was.
 */
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sh2000/run.h>
#include <sh2000/sh2000.h>

#include "upload.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

extern char **environ;

static volatile sig_atomic_t stop_flag, resume_flag;

static void on_stop(int sig)
{
	(void)sig;
	if (stop_flag < 2)
		stop_flag++;
}

static void on_resume(int sig)
{
	(void)sig;
	resume_flag = 1;
}

struct opts {
	const char *device;
	const char *file;
	enum sh2000_prog_format format;
	int rs274;
	const char *trace;
	unsigned int trace_every;
	const char *plot;
	int dry_run, raw, optional_stop, no_enable, quiet, trapezoid;
	double override;	/* factor */
	double feed_mm_min;	/* for CSV and JSON without their own */
};

static void usage(FILE *f)
{
	fprintf(f,
		"Usage: sh2000-upload [-d DEV] [options] FILE\n"
		"Run an NC program (G-code, rs274 canonical output, CSV, JSON NURBS) on an\n"
		"SH-2000TH card. The whole program is read, checked and planned before\n"
		"anything moves.\n"
		"\n"
		"  -d, --device DEV        card: /dev/sh2000-N, io:0xNNN, sim, sim:NAME\n"
		"                          (default $SH2000_DEVICE, else /dev/sh2000-0)\n"
		"  -f, --format FMT        gcode, canon, csv or json (default: from the\n"
		"                          file name: .ngc .nc .gcode .g .tap .cnc .canon\n"
		"                          .csv .json)\n"
		"      --rs274             read G-code through LinuxCNC's rs274 interpreter\n"
		"                          (full RS274NGC; Debian package linuxcnc-uspace)\n"
		"  -F, --feed MM_PER_MIN   feed for CSV and JSON files that carry none\n"
		"  -o, --feed-override PCT feed override, 1..200 %% (default 100)\n"
		"      --raw               no B-spline compensation (the card's spline\n"
		"                          cuts curves; for comparison)\n"
		"      --trapezoid         acceleration-limited profile instead of S-curves\n"
		"  -n, --dry-run           read, check and plan only; nothing moves\n"
		"  -t, --trace FILE.csv    write t,cmd_x,act_x,...,cmd_a,act_a (s, mm): every\n"
		"                          servo cycle on `sim`, every status poll otherwise\n"
		"      --trace-every N     keep every N-th sample in the trace\n"
		"  -p, --plot FILE.png|svg draw the path, feed and following error (gnuplot)\n"
		"      --optional-stop     M1 pauses like M0 (default: M1 is skipped)\n"
		"      --no-enable         do not enable axes; fail if one is disabled\n"
		"  -q, --quiet             no progress output\n"
		"  -h, --help              this text\n"
		"  -V, --version           version\n"
		"\n"
		"M0 (and M1 with --optional-stop) pauses at rest: press Enter on a terminal;\n"
		"otherwise send a line on standard input or SIGUSR1. SIGINT/SIGTERM stop the\n"
		"run on the path (controlled).\n"
		"\n"
		"Exit codes: 0 done, 1 card or I/O error, 2 usage, 3 device cannot be opened,\n"
		"4 card fault or emergency stop, 5 program errors (nothing moved),\n"
		"6 rs274 or gnuplot missing or failed, 7 stopped by the operator.\n");
}

static int parse(int argc, char **argv, struct opts *o)
{
	static const struct option lo[] = {
		{ "device", required_argument, NULL, 'd' },
		{ "format", required_argument, NULL, 'f' },
		{ "rs274", no_argument, NULL, 'R' },
		{ "feed", required_argument, NULL, 'F' },
		{ "feed-override", required_argument, NULL, 'o' },
		{ "raw", no_argument, NULL, 'r' },
		{ "trapezoid", no_argument, NULL, 'T' },
		{ "dry-run", no_argument, NULL, 'n' },
		{ "trace", required_argument, NULL, 't' },
		{ "trace-every", required_argument, NULL, 'e' },
		{ "plot", required_argument, NULL, 'p' },
		{ "optional-stop", no_argument, NULL, 'O' },
		{ "no-enable", no_argument, NULL, 'E' },
		{ "quiet", no_argument, NULL, 'q' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	double v;
	long l;
	int c;

	memset(o, 0, sizeof(*o));
	o->override = 1.0;
	o->trace_every = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+d:f:F:o:nt:p:qhV", lo,
				NULL)) != -1) {
		switch (c) {
		case 'd':
			o->device = optarg;
			break;
		case 'f':
			if (!strcasecmp(optarg, "gcode") ||
			    !strcasecmp(optarg, "ngc"))
				o->format = SH2000_PROG_GCODE;
			else if (!strcasecmp(optarg, "canon"))
				o->format = SH2000_PROG_CANON;
			else if (!strcasecmp(optarg, "csv"))
				o->format = SH2000_PROG_CSV;
			else if (!strcasecmp(optarg, "json") ||
				 !strcasecmp(optarg, "nurbs"))
				o->format = SH2000_PROG_NURBS_JSON;
			else
				return sh2000_tool_usage(NULL,
					"--format %s: expected gcode, canon, csv or json",
					optarg);
			break;
		case 'R':
			o->rs274 = 1;
			break;
		case 'F':
			if (sh2000_tool_double(optarg, &v) || !(v > 0.0))
				return sh2000_tool_usage(NULL,
					"--feed %s: expected a feed > 0 in mm/min",
					optarg);
			o->feed_mm_min = v;
			break;
		case 'o':
			if (sh2000_tool_double(optarg, &v) || !(v >= 1.0) ||
			    v > 200.0)
				return sh2000_tool_usage(NULL,
					"--feed-override %s: expected a percentage 1..200",
					optarg);
			o->override = v / 100.0;
			break;
		case 'r':
			o->raw = 1;
			break;
		case 'T':
			o->trapezoid = 1;
			break;
		case 'n':
			o->dry_run = 1;
			break;
		case 't':
			o->trace = optarg;
			break;
		case 'e':
			if (sh2000_tool_long(optarg, 1, 1000000, &l))
				return sh2000_tool_usage(NULL,
					"--trace-every %s: expected an integer 1..1000000",
					optarg);
			o->trace_every = (unsigned int)l;
			break;
		case 'p':
			o->plot = optarg;
			break;
		case 'O':
			o->optional_stop = 1;
			break;
		case 'E':
			o->no_enable = 1;
			break;
		case 'q':
			o->quiet = 1;
			break;
		case 'h':
			usage(stdout);
			exit(SH2000_EXIT_OK);
		case 'V':
			sh2000_tool_print_version(SH2000_TOOLS_VERSION);
			exit(SH2000_EXIT_OK);
		default:
			if (optopt && strchr("dfFotpe", optopt))
				return sh2000_tool_usage(NULL, "option -%c needs a value",
							 optopt);
			return sh2000_tool_usage(NULL, "unknown option '%s'",
						 argv[optind - 1]);
		}
	}
	if (optind >= argc)
		return sh2000_tool_usage(NULL, "no program file");
	if (optind + 1 < argc)
		return sh2000_tool_usage(NULL, "one program file at a time (got '%s' too)",
					 argv[optind + 1]);
	o->file = argv[optind];
	if (o->plot) {
		size_t n = strlen(o->plot);

		if (n < 5 || (strcasecmp(o->plot + n - 4, ".png") &&
			      strcasecmp(o->plot + n - 4, ".svg")))
			return sh2000_tool_usage(NULL,
				"--plot %s: the name must end in .png or .svg",
				o->plot);
	}
	if (o->rs274 && o->format && o->format != SH2000_PROG_GCODE)
		return sh2000_tool_usage(NULL, "--rs274 reads G-code only");
	return SH2000_EXIT_OK;
}

/* ---- reading ----------------------------------------------------------- */

/* rs274 -g -t tool.tbl -v empty.var FILE > DIR/NAME.canon; the canonical
 * file's name in *canon. */
static int run_rs274(const char *file, char *dir, char *canon, size_t len)
{
	char tbl[128], var[128];
	char *argv[] = { "rs274", "-g", "-t", tbl, "-v", var, (char *)file,
			 NULL };
	posix_spawn_file_actions_t fa;
	int fd, e, status;
	pid_t pid;

	snprintf(dir, 64, "/tmp/sh2000-rs274.XXXXXX");
	if (!mkdtemp(dir)) {
		sh2000_tool_msg("--rs274: temporary directory: %s",
				strerror(errno));
		dir[0] = 0;
		return SH2000_EXIT_CARD;
	}
	snprintf(tbl, sizeof(tbl), "%s/tool.tbl", dir);
	snprintf(var, sizeof(var), "%s/empty.var", dir);
	snprintf(canon, len, "%s/rs274.canon", dir);
	fd = open(tbl, O_WRONLY | O_CREAT | O_TRUNC, 0600);
	if (fd >= 0)
		close(fd);
	fd = open(var, O_WRONLY | O_CREAT | O_TRUNC, 0600);
	if (fd >= 0)
		close(fd);
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
	posix_spawn_file_actions_addopen(&fa, 1, canon,
					 O_WRONLY | O_CREAT | O_TRUNC, 0600);
	e = posix_spawnp(&pid, "rs274", &fa, NULL, argv, environ);
	posix_spawn_file_actions_destroy(&fa);
	if (e) {
		sh2000_tool_msg("--rs274: cannot run rs274: %s", strerror(e));
		return UPLOAD_EXIT_HELPER;
	}
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR)
			return UPLOAD_EXIT_HELPER;
	/* rs274 stops printing at an error; the reader then finds no
	 * PROGRAM_END and says so, after rs274's own message */
	if (!WIFEXITED(status))
		sh2000_tool_msg("--rs274: rs274 ended by signal %d",
				WTERMSIG(status));
	return SH2000_EXIT_OK;
}

static void rs274_cleanup(const char *dir)
{
	static const char *const names[] = { "tool.tbl", "empty.var",
					     "rs274.canon" };
	char p[160];

	if (!dir[0])
		return;
	for (size_t i = 0; i < 3; i++) {
		snprintf(p, sizeof(p), "%s/%s", dir, names[i]);
		unlink(p);
	}
	rmdir(dir);
}

static int read_program(const struct opts *o, const double start[4],
			struct sh2000_program *prog)
{
	struct sh2000_prog_options po;
	struct sh2000_prog_diags d;
	char dir[64] = "", canon[128];
	int r, rc = SH2000_EXIT_OK;

	sh2000_prog_options_default(&po);
	memcpy(po.start, start, sizeof(po.start));
	po.feed_mm_s = o->feed_mm_min / 60.0;
	sh2000_prog_diags_init(&d);
	if (o->rs274) {
		rc = run_rs274(o->file, dir, canon, sizeof(canon));
		if (!rc)
			r = sh2000_program_read_file(prog, SH2000_PROG_CANON,
						     canon, &po, &d);
	} else {
		r = sh2000_program_read_file(prog, o->format, o->file, &po, &d);
	}
	if (!rc) {
		sh2000_prog_diags_print(&d, stderr);
		if (r == -SH2000_PROG_EFORMAT) {
			rc = sh2000_tool_usage(NULL,
				"%s: cannot tell the format from the name; use --format",
				o->file);
		} else if (r == -SH2000_PROG_EINVALID ||
			   (r >= 0 && d.errors)) {
			sh2000_tool_msg("%s: %zu error%s; nothing moved",
					o->file, d.errors,
					d.errors == 1 ? "" : "s");
			if (o->rs274) {
				/* the positions point into rs274's output */
				sh2000_tool_msg("--rs274: rs274's output is kept in %s",
						canon);
				dir[0] = 0;
			}
			rc = UPLOAD_EXIT_PROGRAM;
		} else if (r < 0) {
			/* the file cannot be read: an I/O error, not the
			 * program's */
			if (!d.count)
				sh2000_tool_msg("%s: %s", o->file,
						sh2000_strerror(r));
			rc = SH2000_EXIT_CARD;
		}
	}
	rs274_cleanup(dir);
	sh2000_prog_diags_free(&d);
	return rc;
}

/* ---- the checking plan -------------------------------------------------- */

struct check {
	const struct sh2000_program *prog;
	struct sh2000_limits limits;	/* the card's soft limits */
	int32_t start[SH2000_AXES];
	unsigned int moved;		/* axes any point moves */
	uint64_t points;
	int bad;
	char msg[256];
	uint32_t bad_seq;
};

static int check_sink(void *ctx, const struct sh2000_path_point *pt)
{
	struct check *c = ctx;
	double mm[SH2000_AXES];
	unsigned int a;

	c->points++;
	for (a = 0; a < SH2000_AXES; a++)
		if (pt->counts[a] != c->start[a])
			c->moved |= 1u << a;
	/* the runner applies the same rule to the same points later */
	memcpy(mm, pt->mm, sizeof(mm));
	if (sh2000_limits_apply(&c->limits, mm, c->msg, sizeof(c->msg)) < 0) {
		c->bad = 1;
		c->bad_seq = pt->seq;
		return -SH2000_ELIMIT;
	}
	return 0;
}

static void block_error(const struct sh2000_program *prog, size_t i,
			const char *msg)
{
	char where[300];

	if (i < prog->count)
		sh2000_prog_block_where(&prog->blocks[i], where, sizeof(where));
	else
		snprintf(where, sizeof(where), "%s", prog->file);
	fprintf(stderr, "%s: error: %s\n", where, msg);
}

/* Plan the whole program with a sink that only checks. */
static int check_plan(const struct opts *o, const struct sh2000_path_config *pc,
		      const struct sh2000_program *prog, struct check *c,
		      double *seconds)
{
	struct sh2000_path *p;
	char err[256];
	double dwell = 0.0;
	size_t i;
	int r = 0;

	c->prog = prog;
	if (sh2000_path_create(&p, pc, check_sink, c, err, sizeof(err))) {
		sh2000_tool_msg("planner: %s", err);
		return SH2000_EXIT_CARD;
	}
	sh2000_path_set_override(p, o->override);
	for (i = 0; i < prog->count && !r; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		if (b->kind == SH2000_PROG_END)
			break;
		if (b->kind == SH2000_PROG_DWELL ||
		    (b->kind == SH2000_PROG_PAUSE &&
		     (!b->u.optional || o->optional_stop))) {
			r = sh2000_path_finish(p);
			if (b->kind == SH2000_PROG_DWELL)
				dwell += b->u.dwell_s;
			continue;
		}
		/* the points of a motion carry its block (the tail after it
		 * too: the tag changes only with the next motion) */
		sh2000_path_set_seq(p, (uint32_t)i);
		r = sh2000_path_add_block(p, b);
	}
	if (!r)
		r = sh2000_path_finish(p);
	if (r) {
		if (c->bad)
			block_error(prog, c->bad_seq, c->msg);
		else
			block_error(prog, i ? i - 1 : 0, sh2000_path_error(p));
		sh2000_tool_msg("%s: the plan failed; nothing moved", o->file);
		sh2000_path_destroy(p);
		return UPLOAD_EXIT_PROGRAM;
	}
	*seconds = (double)c->points * pc->period_s + dwell;
	sh2000_path_destroy(p);
	return SH2000_EXIT_OK;
}

/* ---- running ------------------------------------------------------------ */

struct runctx {
	struct sh2000 *h;
	struct sh2000_run *run;
	struct upl_trace *trace;
	struct upl_report rep;
	int stop_sent, estop_sent;
	int64_t seq;		/* the block the card was at, last poll */
};

static void on_sample(void *ctx, const struct sh2000_run_sample *s)
{
	struct runctx *rc = ctx;

	if (rc->trace)
		upl_trace_sample(rc->trace, s);
}

static void on_progress(void *ctx, const struct sh2000_run_progress *p)
{
	struct runctx *rc = ctx;

	if (stop_flag && !rc->stop_sent && rc->run) {
		rc->stop_sent = 1;
		upl_report_end(&rc->rep);
		sh2000_tool_msg("stopping on the path (signal; a second one is an emergency stop)");
		sh2000_run_stop(rc->run);
	}
	if (stop_flag >= 2 && !rc->estop_sent && rc->h) {
		rc->estop_sent = 1;
		upl_report_end(&rc->rep);
		sh2000_tool_msg("emergency stop (second signal)");
		sh2000_estop(rc->h, 100);
	}
	if (p->seq >= 0)
		rc->seq = p->seq;
	upl_report_progress(&rc->rep, p);
}

/* M0/M1: wait at rest for the operator. 0 to go on, else an exit code. */
static int operator_pause(struct sh2000 *h, struct runctx *rc,
			  const struct sh2000_prog_block *b, int *stdin_eof)
{
	char where[300];
	int tty = isatty(STDIN_FILENO);

	upl_report_end(&rc->rep);
	sh2000_prog_block_where(b, where, sizeof(where));
	if (tty)
		sh2000_tool_msg("%s: %s: paused; press Enter to resume (Ctrl-C stops)",
				where, b->u.optional ? "M1" : "M0");
	else
		sh2000_tool_msg("%s: %s: paused; resuming on a line on standard input or SIGUSR1 (pid %ld)",
				where, b->u.optional ? "M1" : "M0",
				(long)getpid());
	resume_flag = 0;
	for (;;) {
		struct pollfd pf = { .fd = STDIN_FILENO, .events = POLLIN };
		int n;

		if (stop_flag)
			return UPLOAD_EXIT_STOPPED;
		if (resume_flag)
			break;
		n = poll(&pf, *stdin_eof ? 0 : 1, 200);
		if (n > 0) {
			char ch;
			ssize_t k;

			while ((k = read(STDIN_FILENO, &ch, 1)) == 1 &&
			       ch != '\n')
				;
			if (k == 1)
				break;
			if (k == 0 || (k < 0 && errno != EINTR && errno != EAGAIN))
				*stdin_eof = 1;
		}
		if (sh2000_backend(h) != SH2000_BACKEND_SIM) {
			struct sh2000_status st;
			int e = sh2000_poll(h, &st);

			if (e >= 0)
				e = sh2000_status_error(h, &st);
			if (e < 0)
				return sh2000_tool_fail(h, e, "while paused");
		}
	}
	sh2000_tool_msg("resuming");
	return SH2000_EXIT_OK;
}

static int run_fail(const struct sh2000_program *prog,
		    const struct runctx *rc, int e)
{
	char where[300] = "";

	/* a long path fills where: the separator goes in at print time */
	if (rc->seq >= 0 && (uint64_t)rc->seq < prog->count)
		sh2000_prog_block_where(&prog->blocks[rc->seq], where, sizeof(where));
	if (e == -ECANCELED) {
		sh2000_tool_msg("%s%sstopped by the operator; the card is at rest on the path",
				where, where[0] ? ": " : "");
		return UPLOAD_EXIT_STOPPED;
	}
	sh2000_tool_msg("%s", sh2000_run_error(rc->run));
	if (where[0])
		sh2000_tool_msg("%s: the card was running this block", where);
	if (e == -SH2000_ESTOPPED)
		return UPLOAD_EXIT_STOPPED;	/* an operator's STOP elsewhere */
	return sh2000_tool_exit_code(e);
}

static int execute(struct sh2000 *h, const struct opts *o,
		   const struct sh2000_program *prog, struct runctx *rc)
{
	int stdin_eof = 0, m1_note = 0, e = 0, x;
	size_t i;

	for (i = 0; i < prog->count && !stop_flag; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		if (b->kind == SH2000_PROG_END)
			break;
		switch (b->kind) {
		case SH2000_PROG_PAUSE:
			if (b->u.optional && !o->optional_stop) {
				if (!m1_note++ && !o->quiet)
					sh2000_tool_msg("M1 optional stops are skipped (--optional-stop pauses at them)");
				continue;
			}
			e = sh2000_run_finish(rc->run);
			if (e)
				return run_fail(prog, rc, e);
			x = operator_pause(h, rc, b, &stdin_eof);
			if (x)
				return x;
			continue;
		case SH2000_PROG_DWELL:
			e = sh2000_run_finish(rc->run);
			if (!e)
				e = sh2000_run_dwell(rc->run, b->u.dwell_s);
			if (e)
				return run_fail(prog, rc, e);
			continue;
		default:
			sh2000_path_set_seq(sh2000_run_path(rc->run),
					    (uint32_t)i);
			e = sh2000_path_add_block(sh2000_run_path(rc->run), b);
			if (e) {
				/* checked before: a card failure while the
				 * look-ahead streamed, or a stop */
				e = sh2000_run_finish(rc->run);
				if (!e)
					e = -EIO;
				return run_fail(prog, rc, e);
			}
		}
	}
	e = sh2000_run_finish(rc->run);
	if (!e && stop_flag)
		e = -ECANCELED;
	if (e)
		return run_fail(prog, rc, e);
	return SH2000_EXIT_OK;
}

static void axes_text(unsigned int mask, char *buf)
{
	unsigned int a;
	char *p = buf;

	for (a = 0; a < SH2000_AXES; a++)
		if (mask & (1u << a)) {
			if (p != buf)
				*p++ = ' ';
			*p++ = (char)('x' + (a == 3 ? -23 : (int)a));
		}
	*p = 0;
}

static int enable_axes(struct sh2000 *h, const struct opts *o,
		       unsigned int need)
{
	struct sh2000_status st;
	unsigned int off = 0, a;
	char names[16];
	int e;

	e = sh2000_poll(h, &st);
	if (e < 0)
		return sh2000_tool_fail(h, e, "status");
	for (a = 0; a < SH2000_AXES; a++)
		if ((need & (1u << a)) &&
		    !(st.axis[a].state & SH2000_AXIS_ENABLED))
			off |= 1u << a;
	if (!off)
		return SH2000_EXIT_OK;
	axes_text(off, names);
	if (o->no_enable) {
		sh2000_tool_msg("%s: axes %s not enabled (--no-enable; enable them with sh2000ctl enable); nothing moved",
				sh2000_device(h), names);
		return SH2000_EXIT_CARD;
	}
	if (!o->quiet)
		sh2000_tool_msg("%s: enabling axes %s", sh2000_device(h), names);
	e = sh2000_enable(h, off);
	if (e < 0)
		return sh2000_tool_fail(h, e, "enable");
	return SH2000_EXIT_OK;
}

static void summary(const struct opts *o, struct sh2000 *h,
		    const struct sh2000_run_stats *s, double planned,
		    const struct upl_trace *t)
{
	printf("sh2000-upload: %s on %s: done\n", o->file, sh2000_device(h));
	printf("  time                 %.3f s of card time (planned %.3f s)\n",
	       s->time_s, planned);
	printf("  distance             %.3f mm\n", s->distance_mm);
	printf("  points               %llu coarse points in %llu batches\n",
	       (unsigned long long)s->points, (unsigned long long)s->batches);
	printf("  max following error  %.4f mm (axis %c, %s)\n",
	       s->max_ferr_mm, "xyza"[s->max_ferr_axis % 4],
	       sh2000_backend(h) == SH2000_BACKEND_SIM ? "every servo cycle" :
	       "at status polls");
	if (s->min_fill < sh2000_queue_size(h))
		printf("  underruns            %llu (ring low-water mark %u of %u records)\n",
		       (unsigned long long)s->underruns, s->min_fill,
		       sh2000_queue_size(h));
	else
		printf("  underruns            %llu\n",
		       (unsigned long long)s->underruns);
	printf("  B-spline compensation %s\n", o->raw ? "off (--raw)" : "on");
	if (o->trace)
		printf("  trace                %s (%llu rows)\n", o->trace,
		       (unsigned long long)upl_trace_rows(t));
}

int main(int argc, char **argv)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rcfg;
	struct sh2000_run_stats stats;
	struct sh2000_program prog;
	struct sh2000_status st;
	struct sigaction sa;
	struct check chk;
	struct runctx rc;
	struct sh2000 *h = NULL;
	struct opts o;
	double planned = 0.0, v;
	char msg[512];
	unsigned int a;
	int x, e;

	sh2000_tool_init("sh2000-upload");
	x = parse(argc, argv, &o);
	if (x)
		return x;
	/* helpers first: a missing one must not cost a run */
	if (o.rs274 && !upl_which("rs274")) {
		sh2000_tool_msg("--rs274: LinuxCNC's rs274 interpreter is not installed (Debian package linuxcnc-uspace); without --rs274 the built-in parser reads the G-code subset");
		return UPLOAD_EXIT_HELPER;
	}
	if (o.plot && !upl_which("gnuplot")) {
		sh2000_tool_msg("--plot %s: gnuplot not found on PATH (Debian package gnuplot-nox)",
				o.plot);
		return UPLOAD_EXIT_HELPER;
	}
	x = sh2000_tool_open(&h, o.device);
	if (x)
		return x;
	sh2000_program_init(&prog);
	memset(&rc, 0, sizeof(rc));

	e = sh2000_poll(h, &st);
	if (e < 0) {
		x = sh2000_tool_fail(h, e, "status");
		goto out;
	}
	e = sh2000_status_error(h, &st);
	if (e < 0) {
		x = sh2000_tool_fail(h, e, NULL);
		sh2000_tool_msg("%s: clear it first (sh2000ctl -d %s reset); nothing moved",
				sh2000_device(h), sh2000_device(h));
		goto out;
	}
	if (st.card_state != SH2000_STATE_IDLE || st.queue_fill) {
		sh2000_tool_msg("%s: the card is busy (state %u, %u records queued); nothing moved",
				sh2000_device(h), st.card_state, st.queue_fill);
		x = SH2000_EXIT_CARD;
		goto out;
	}
	e = sh2000_run_path_config(h, &pc);
	if (e < 0) {
		x = sh2000_tool_fail(h, e, "reading the card's parameters");
		goto out;
	}
	pc.output = o.raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
	if (o.trapezoid)
		pc.profile = SH2000_PROFILE_TRAPEZOID;

	x = read_program(&o, pc.start, &prog);
	if (x)
		goto out;

	memset(&chk, 0, sizeof(chk));
	e = sh2000_limits_get(h, &chk.limits);
	if (e) {
		x = sh2000_tool_fail(h, e, "soft limits");
		goto out;
	}
	for (a = 0; a < SH2000_AXES; a++)
		chk.start[a] = (int32_t)llround(pc.start[a] * pc.counts_per_mm[a]);
	x = check_plan(&o, &pc, &prog, &chk, &planned);
	if (x)
		goto out;
	if (o.dry_run) {
		char names[16];

		axes_text(chk.moved, names);
		printf("sh2000-upload: %s: %zu blocks checked and planned; nothing moved (--dry-run)\n",
		       o.file, prog.count);
		printf("  planned time         %.3f s (%llu points of %.1f ms)\n",
		       planned, (unsigned long long)chk.points,
		       pc.period_s * 1e3);
		printf("  axes moved           %s\n", chk.moved ? names : "none");
		x = SH2000_EXIT_OK;
		goto out;
	}

	if (o.trace || o.plot) {
		rc.trace = upl_trace_open(o.trace, o.trace_every, !!o.plot, msg,
					  sizeof(msg));
		if (!rc.trace) {
			sh2000_tool_msg("%s; nothing moved", msg);
			x = SH2000_EXIT_CARD;
			goto out;
		}
	}
	x = enable_axes(h, &o, chk.moved);
	if (x)
		goto out;
	/* the plan starts where the card holds now (enabling keeps the
	 * position; a card that moved meanwhile is refused) */
	{
		double start[SH2000_AXES];

		memcpy(start, pc.start, sizeof(start));
		e = sh2000_run_path_config(h, &pc);
		if (e < 0) {
			x = sh2000_tool_fail(h, e, "status");
			goto out;
		}
		pc.output = o.raw ? SH2000_OUTPUT_RAW : SH2000_OUTPUT_COMPENSATED;
		if (o.trapezoid)
			pc.profile = SH2000_PROFILE_TRAPEZOID;
		for (a = 0; a < SH2000_AXES; a++) {
			v = fabs(start[a] - pc.start[a]);
			if (v > 0.001) {
				sh2000_tool_msg("%s: axis %c moved by %.4f mm while the program was checked; nothing moved",
						sh2000_device(h), "xyza"[a], v);
				x = SH2000_EXIT_CARD;
				goto out;
			}
		}
	}

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_stop;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	sa.sa_handler = on_resume;
	sigaction(SIGUSR1, &sa, NULL);

	rc.h = h;
	rc.seq = -1;
	rc.rep.prog = &prog;
	rc.rep.bar = isatty(STDERR_FILENO);
	rc.rep.quiet = o.quiet;
	rc.rep.total_points = chk.points;
	rc.rep.last_pct = -1;
	sh2000_run_config_default(&rcfg);
	rcfg.sample = (o.trace || o.plot) ? on_sample : NULL;
	rcfg.progress = on_progress;
	rcfg.ctx = &rc;
	e = sh2000_run_create(&rc.run, h, &pc, &rcfg, msg, sizeof(msg));
	if (e < 0) {
		sh2000_tool_msg("%s", msg);
		x = sh2000_tool_exit_code(e);
		goto out;
	}
	sh2000_run_set_override(rc.run, o.override);
	x = execute(h, &o, &prog, &rc);
	upl_report_end(&rc.rep);
	sh2000_run_stats(rc.run, &stats);
	if (rc.trace && (e = upl_trace_close_csv(rc.trace)) < 0) {
		sh2000_tool_msg("--trace %s: %s", o.trace, strerror(-e));
		if (!x)
			x = SH2000_EXIT_CARD;
	}
	if (!x)
		summary(&o, h, &stats, planned, rc.trace);
	if (o.plot && rc.trace) {
		char title[512];
		int px;

		snprintf(title, sizeof(title), "%s on %s%s", o.file,
			 sh2000_device(h), o.raw ? " (--raw)" : "");
		px = upl_trace_plot(rc.trace, o.plot, title);
		if (!px && !x)
			printf("  plot                 %s\n", o.plot);
		if (!x)
			x = px;
	}
out:
	fflush(stdout);
	if (rc.run)
		sh2000_run_destroy(rc.run);
	upl_trace_free(rc.trace);
	sh2000_program_free(&prog);
	sh2000_close(h);
	return x;
}
