// SPDX-License-Identifier: MIT
/*
 * The --trace CSV (one row per sample) and the --plot picture: the samples
 * go to a plot data file (one row per millisecond at most), which a
 * generated gnuplot script draws.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "upload.h"

/* Plot rows at least this far apart (s). */
#define PLOT_DT 0.001

struct upl_trace {
	FILE *csv;
	const char *path;		/* the --trace file */
	int created;			/* this run made it (it did not exist) */
	dev_t dev;			/* and which file that is */
	ino_t ino;
	int started;			/* the run began: the header is in */
	unsigned int every;
	uint64_t seen, rows;
	int csv_err;
	FILE *plot;			/* plot data, in tmpdir */
	char dir[64];			/* temporary directory */
	char data[96];
	double last_t;
	double last_cmd[SH2000_AXES];
	int have_last;
	uint64_t plot_rows;
};

int upl_which(const char *prog)
{
	const char *path = getenv("PATH");
	char buf[4096];

	if (strchr(prog, '/'))
		return access(prog, X_OK) == 0;
	if (!path)
		path = "/usr/bin:/bin";
	while (*path) {
		const char *c = strchr(path, ':');
		size_t n = c ? (size_t)(c - path) : strlen(path);

		snprintf(buf, sizeof(buf), "%.*s/%s", (int)n,
			 n ? path : ".", prog);
		if (access(buf, X_OK) == 0)
			return 1;
		path += n;
		if (*path == ':')
			path++;
	}
	return 0;
}

/*
 * The --trace file, opened before anything on the card changes (so a path
 * that cannot be written refuses the run) but neither truncated nor
 * written until the run starts (upl_trace_start): a refused run leaves a
 * user's file as it was, and one this run created is removed again
 * (upl_trace_free). 0, or -1 with the reason in msg.
 */
static int open_csv(struct upl_trace *t, const char *csv, char *msg,
		    size_t len)
{
	struct stat sb;
	int fd = open(csv, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);

	t->created = fd >= 0;
	if (fd < 0 && errno == EEXIST)
		fd = open(csv, O_WRONLY | O_CLOEXEC);
	if (fd < 0 || !(t->csv = fdopen(fd, "w"))) {
		snprintf(msg, len, "--trace %s: %s", csv, strerror(errno));
		if (fd >= 0)
			close(fd);
		if (t->created)
			unlink(csv);
		return -1;
	}
	t->path = csv;
	if (fstat(fd, &sb) == 0) {
		t->dev = sb.st_dev;
		t->ino = sb.st_ino;
	}
	return 0;
}

struct upl_trace *upl_trace_open(const char *csv, unsigned int every,
				 int plot, char *msg, size_t len)
{
	struct upl_trace *t = calloc(1, sizeof(*t));

	if (!t) {
		snprintf(msg, len, "out of memory");
		return NULL;
	}
	t->every = every ? every : 1;
	if (csv && open_csv(t, csv, msg, len) < 0) {
		free(t);
		return NULL;
	}
	if (plot) {
		const char *tmp = getenv("TMPDIR");

		snprintf(t->dir, sizeof(t->dir), "%s/sh2000-upload.XXXXXX",
			 tmp && *tmp && strlen(tmp) < 32 ? tmp : "/tmp");
		if (!mkdtemp(t->dir)) {
			snprintf(msg, len, "--plot: temporary directory %s: %s",
				 t->dir, strerror(errno));
			t->dir[0] = 0;
			upl_trace_free(t);
			return NULL;
		}
		snprintf(t->data, sizeof(t->data), "%s/plot.dat", t->dir);
		t->plot = fopen(t->data, "w");
		if (!t->plot) {
			snprintf(msg, len, "--plot: %s: %s", t->data,
				 strerror(errno));
			upl_trace_free(t);
			return NULL;
		}
	}
	return t;
}

int upl_trace_start(struct upl_trace *t)
{
	struct stat sb;
	int fd;

	if (!t->csv) {
		t->started = 1;
		return 0;
	}
	fd = fileno(t->csv);
	/* a regular file starts empty, as fopen(.., "w") would have made it
	 * (a pipe or a terminal has nothing to cut) */
	if (fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) && ftruncate(fd, 0))
		return -errno;
	if (fputs("t,cmd_x,act_x,cmd_y,act_y,cmd_z,act_z,cmd_a,act_a\n",
		  t->csv) < 0)
		return -(errno ? errno : EIO);
	t->started = 1;		/* not before: a failed start is a refusal */
	return 0;
}

static void plot_row(struct upl_trace *t, const struct sh2000_run_sample *s)
{
	double d = 0.0, e = 0.0, feed = 0.0;
	unsigned int a;

	if (t->have_last && s->t - t->last_t < PLOT_DT - 1e-9)
		return;
	for (a = 0; a < SH2000_AXES; a++) {
		double c = s->cmd[a] - s->act[a];

		e += c * c;
		if (t->have_last)
			d += (s->cmd[a] - t->last_cmd[a]) *
			     (s->cmd[a] - t->last_cmd[a]);
	}
	if (t->have_last && s->t > t->last_t)
		feed = sqrt(d) / (s->t - t->last_t);
	/* t, cmd x y, act x y, feed mm/s, following error um */
	fprintf(t->plot, "%.6f %.6f %.6f %.6f %.6f %.3f %.4f\n", s->t,
		s->cmd[0], s->cmd[1], s->act[0], s->act[1], feed,
		sqrt(e) * 1000.0);
	t->plot_rows++;
	t->last_t = s->t;
	memcpy(t->last_cmd, s->cmd, sizeof(t->last_cmd));
	t->have_last = 1;
}

void upl_trace_sample(struct upl_trace *t, const struct sh2000_run_sample *s)
{
	/* the card model's observer is in before the run starts: the trace
	 * begins with the run */
	if (!t->started)
		return;
	if (t->csv && t->seen++ % t->every == 0) {
		if (fprintf(t->csv,
			    "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n",
			    s->t, s->cmd[0], s->act[0], s->cmd[1], s->act[1],
			    s->cmd[2], s->act[2], s->cmd[3], s->act[3]) < 0)
			t->csv_err = errno ? errno : EIO;
		t->rows++;
	}
	if (t->plot)
		plot_row(t, s);
}

int upl_trace_close_csv(struct upl_trace *t)
{
	int e = t->csv_err;

	if (t->csv) {
		if (fclose(t->csv) && !e)
			e = errno ? errno : EIO;
		t->csv = NULL;
	}
	return -e;
}

uint64_t upl_trace_rows(const struct upl_trace *t)
{
	return t->rows;
}

static int write_script(FILE *f, const void *ctx, const char *out,
			const struct sh2000_tool_plot_kind *k)
{
	sh2000_tool_plot_head(f, out, (const char *)ctx, k, 1400, 900);
	fputs("set datafile separator ' '\n"
	      /* left: the path in XY, true to scale */
	      "set origin 0,0\nset size 0.5,0.95\n"
	      "set size ratio -1\n"
	      "set title 'path (XY)'\nset xlabel 'x (mm)'\nset ylabel 'y (mm)'\n"
	      "set key bottom right\n"
	      /* the encoder wide and pale under the set-point: where they
	       * agree the set-point shows with a halo */
	      "plot DATA using 4:5 with lines lw 5 lc rgb '#f4a582' title 'encoder', \\\n"
	      "     DATA using 2:3 with lines lw 1.5 lc rgb '#1f5fb4' title 'set-point'\n"
	      "set size noratio\n"
	      /* right, top: the path feed */
	      "set origin 0.5,0.475\nset size 0.5,0.475\n"
	      "set title 'feed'\nset xlabel 't (s)'\nset ylabel 'mm/s'\n"
	      "set yrange [0:*]\n"
	      "set key top right\n"
	      "plot DATA using 1:6 with lines lc rgb '#1f6fd0' title 'path velocity of the set-point'\n"
	      /* right, bottom: the following error */
	      "set origin 0.5,0\nset size 0.5,0.475\n"
	      "set title 'following error'\nset xlabel 't (s)'\nset ylabel 'um'\n"
	      "set yrange [0:*]\n"
	      "plot DATA using 1:7 with lines lc rgb '#d03a1f' title '|set-point - encoder|'\n"
	      "unset multiplot\n", f);
	return 0;
}

int upl_trace_plot(struct upl_trace *t, const char *out, const char *title)
{
	if (!t->plot)
		return SH2000_EXIT_OK;
	if (fclose(t->plot)) {
		t->plot = NULL;
		sh2000_tool_msg("--plot: %s: %s", t->data, strerror(errno));
		return SH2000_EXIT_CARD;
	}
	t->plot = NULL;
	if (!t->plot_rows) {
		sh2000_tool_msg("--plot %s: no samples to draw", out);
		return SH2000_EXIT_CARD;
	}
	return sh2000_tool_plot(t->dir, t->data, out, write_script, title);
}

void upl_trace_free(struct upl_trace *t)
{
	struct stat sb;

	if (!t)
		return;
	if (t->csv)
		fclose(t->csv);
	/* a refused run: the file it created goes (the same file only) */
	if (t->path && t->created && !t->started &&
	    stat(t->path, &sb) == 0 && sb.st_dev == t->dev &&
	    sb.st_ino == t->ino)
		unlink(t->path);
	if (t->plot)
		fclose(t->plot);
	if (t->dir[0]) {
		/* the runner removed its script and gnuplot's stderr */
		unlink(t->data);
		rmdir(t->dir);
	}
	free(t);
}
