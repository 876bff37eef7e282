/* SPDX-License-Identifier: MIT */
/*
 * A program outside the project that runs an NC program on a card with
 * nothing but the installed libsh2000-motion and libsh2000 (headers from
 * <prefix>/include, libraries found by pkg-config or find_package):
 *
 *   runpart DEVICE FILE        e.g. runpart sim examples/part.ngc
 *
 * It reads FILE, plans and streams every block through a run
 * (sh2000/run.h), then checks that the card came to rest where the
 * program ends: each axis' encoder within 1 um of the last block's end
 * point. Exit 0 when it did, 1 otherwise.
 */
#include <sh2000/program.h>
#include <sh2000/run.h>
#include <sh2000/sh2000.h>

#include <math.h>
#include <stdio.h>

#define ALL_AXES	((1u << SH2000_AXES) - 1u)
#define END_TOL_MM	0.001

static int fail(const char *what, const char *msg)
{
	fprintf(stderr, "runpart: %s: %s\n", what, msg);
	return 1;
}

static int read_program(struct sh2000_program *prog, const char *file,
			const double start[SH2000_AXES])
{
	struct sh2000_prog_options opt;
	struct sh2000_prog_diags diags;
	unsigned int a;
	int r;

	sh2000_prog_options_default(&opt);
	for (a = 0; a < SH2000_AXES; a++)
		opt.start[a] = start[a];
	sh2000_prog_diags_init(&diags);
	r = sh2000_program_read_file(prog, SH2000_PROG_AUTO, file, &opt, &diags);
	sh2000_prog_diags_print(&diags, stderr);
	sh2000_prog_diags_free(&diags);
	if (r < 0)
		return fail(file, sh2000_strerror(r));
	return 0;
}

/*
 * Every block up to END: motion blocks into the planner, which streams
 * them; a dwell waits on the card at rest; M0 comes to rest and goes on
 * (there is no operator here), an optional stop (M1) is skipped. FEED
 * changes nothing to do: each motion block carries its feed.
 * Returns 0 and the point where the program ends in end[], or 1.
 */
static int run_blocks(struct sh2000_run *run,
		      const struct sh2000_program *prog, double *end)
{
	char where[300];
	unsigned int a;
	size_t i;
	int r = 0;

	for (i = 0; i < prog->count && !r; i++) {
		const struct sh2000_prog_block *b = &prog->blocks[i];

		for (a = 0; a < SH2000_AXES; a++)
			end[a] = b->end[a];
		if (b->kind == SH2000_PROG_END)
			break;
		switch (b->kind) {
		case SH2000_PROG_FEED:
			continue;
		case SH2000_PROG_PAUSE:
			if (!b->u.optional)
				r = sh2000_run_finish(run);
			continue;
		case SH2000_PROG_DWELL:
			r = sh2000_run_finish(run);
			if (!r)
				r = sh2000_run_dwell(run, b->u.dwell_s);
			continue;
		default:
			r = sh2000_path_add_block(sh2000_run_path(run), b);
			if (r) {
				sh2000_prog_block_where(b, where, sizeof(where));
				fprintf(stderr, "runpart: %s: %s\n", where,
					sh2000_path_error(sh2000_run_path(run)));
			}
		}
	}
	if (!r)
		r = sh2000_run_finish(run);
	if (r)
		return fail("run", sh2000_run_error(run));
	return 0;
}

/* Encoder positions against the end point, one line per axis. */
static int check_end(struct sh2000 *h, const double end[SH2000_AXES])
{
	static const char names[SH2000_AXES + 1] = "XYZA";
	struct sh2000_status st;
	unsigned int a;
	int r, bad = 0;

	r = sh2000_poll(h, &st);
	if (r < 0)
		return fail("poll", sh2000_strerror(r));
	for (a = 0; a < SH2000_AXES; a++) {
		double d = st.axis[a].pos_mm - end[a];
		int off = !(fabs(d) <= END_TOL_MM);

		printf("runpart: %c at %.6f mm, program ends at %.6f mm (%+.4f um)%s\n",
		       names[a], st.axis[a].pos_mm, end[a], d * 1000.0,
		       off ? ": off by more than 1 um" : "");
		bad |= off;
	}
	return bad;
}

static int run_program(struct sh2000 *h, const char *file)
{
	struct sh2000_path_config pc;
	struct sh2000_run_config rc;
	struct sh2000_run_stats stats;
	struct sh2000_program prog;
	struct sh2000_run *run;
	double end[SH2000_AXES];
	char msg[256];
	int r;

	r = sh2000_run_path_config(h, &pc);
	if (r < 0)
		return fail("path config", sh2000_strerror(r));
	sh2000_program_init(&prog);
	r = read_program(&prog, file, pc.start);
	if (r) {
		sh2000_program_free(&prog);
		return r;
	}
	sh2000_run_config_default(&rc);
	if (sh2000_run_create(&run, h, &pc, &rc, msg, sizeof(msg)) < 0) {
		sh2000_program_free(&prog);
		return fail("run", msg);
	}
	r = run_blocks(run, &prog, end);
	if (!r) {
		sh2000_run_stats(run, &stats);
		printf("runpart: %llu points in %.3f s of card time\n",
		       (unsigned long long)stats.points, stats.time_s);
		r = check_end(h, end);
	}
	printf("runpart: %s: %zu blocks of %s on %s with libsh2000 %s: %s\n",
	       r ? "FAIL" : "ok", prog.count, file, sh2000_device(h),
	       sh2000_version(), r ? "not at the end point" : "at the end point");
	sh2000_run_destroy(run);
	sh2000_program_free(&prog);
	return r;
}

int main(int argc, char **argv)
{
	struct sh2000 *h;
	char msg[256];
	int r;

	if (argc != 3) {
		fprintf(stderr, "usage: runpart DEVICE FILE\n");
		return 2;
	}
	if (sh2000_open(&h, argv[1], msg, sizeof(msg)) < 0)
		return fail(argv[1], msg);
	r = sh2000_enable(h, ALL_AXES);
	if (r < 0)
		r = fail("enable", sh2000_last_error(h));
	else
		r = run_program(h, argv[2]);
	sh2000_close(h);
	return r;
}
