/* SPDX-License-Identifier: MIT */
/*
 * The tools' one gnuplot runner (Debian's gnuplot-nox): a picture drawn
 * from a data file by a script the tool writes, PNG through pngcairo when
 * this gnuplot has it (it draws better), else libgd's png, or SVG; the
 * messages and exit codes the same for every tool's --plot.
 */
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/wait.h>
#include <unistd.h>

#include "toolcommon.h"

extern char **environ;

/* Run "gnuplot -e DEF SCRIPT", its stdout to /dev/null and stderr into
 * errfile; *status as waitpid() gives it. 0, or -errno when it cannot run
 * (-ENOENT: not on PATH). */
static int run(const char *def, const char *script, const char *errfile,
	       int *status)
{
	posix_spawn_file_actions_t fa;
	char *argv[] = { "gnuplot", "-e", (char *)def, (char *)script, NULL };
	pid_t pid;
	int e;

	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
	posix_spawn_file_actions_addopen(&fa, 2, errfile,
					 O_WRONLY | O_CREAT | O_TRUNC, 0600);
	e = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
	posix_spawn_file_actions_destroy(&fa);
	if (e)
		return -e;
	while (waitpid(pid, status, 0) < 0)
		if (errno != EINTR)
			return -errno;
	return 0;
}

void sh2000_tool_gnuplot_quoted(FILE *f, const char *s)
{
	fputc('\'', f);
	for (; *s; s++)
		fputc(*s == '\'' ? '_' : *s, f);
	fputc('\'', f);
}

void sh2000_tool_plot_head(FILE *f, const char *out, const char *title,
			   const struct sh2000_tool_plot_kind *k,
			   unsigned int width, unsigned int height)
{
	if (k->svg)
		fprintf(f, "set terminal svg size %u,%u dynamic font 'Sans,11'\n",
			width, height);
	else if (k->cairo)
		fprintf(f, "set terminal pngcairo size %u,%u font 'Sans,10'\n",
			width, height);
	else
		fprintf(f, "set terminal png size %u,%u\n", width, height);
	fputs("set output ", f);
	sh2000_tool_gnuplot_quoted(f, out);
	fputs("\nset grid\nset multiplot title ", f);
	sh2000_tool_gnuplot_quoted(f, title);
	fputs("\n", f);
}

/* The script written and closed: 0 or -errno. */
static int script_file(const char *path, const char *out,
		       const struct sh2000_tool_plot_kind *k,
		       sh2000_tool_plot_script write_script, const void *ctx)
{
	FILE *f = fopen(path, "w");
	int e;

	if (!f)
		return -errno;
	e = write_script(f, ctx, out, k);
	if (fclose(f) && !e)
		e = -errno;
	return e;
}

/* gnuplot ran and failed: its status and its stderr, indented. */
static int report_failure(const char *out, const char *errfile, int status)
{
	char line[512];
	FILE *f;

	sh2000_tool_msg("--plot %s: gnuplot failed (%s %d):", out,
			WIFEXITED(status) ? "exit status" : "signal",
			WIFEXITED(status) ? WEXITSTATUS(status) :
			WTERMSIG(status));
	f = fopen(errfile, "r");
	while (f && fgets(line, sizeof(line), f))
		fprintf(stderr, "  %s", line);
	if (f)
		fclose(f);
	return SH2000_EXIT_HELPER;
}

int sh2000_tool_plot(const char *dir, const char *data, const char *out,
		     sh2000_tool_plot_script write_script, const void *ctx)
{
	struct sh2000_tool_plot_kind k = { 0, 1 };
	char script[256], errfile[256], def[300];
	size_t n = strlen(out);
	int status = 0, e = 0, r;

	k.svg = n >= 4 && !strcasecmp(out + n - 4, ".svg");
	snprintf(script, sizeof(script), "%s/plot.gp", dir);
	snprintf(errfile, sizeof(errfile), "%s/gnuplot.err", dir);
	snprintf(def, sizeof(def), "DATA='%s'", data);
	for (; k.cairo >= 0; k.cairo--) {
		e = script_file(script, out, &k, write_script, ctx);
		if (e) {
			sh2000_tool_msg("--plot: %s: %s", script, strerror(-e));
			r = SH2000_EXIT_CARD;
			goto out;
		}
		e = run(def, script, errfile, &status);
		if (e || (WIFEXITED(status) && WEXITSTATUS(status) == 0) ||
		    k.svg)
			break;
	}
	if (e == -ENOENT)
		sh2000_tool_msg("--plot %s: gnuplot not found on PATH (Debian package gnuplot-nox)",
				out);
	else if (e)
		sh2000_tool_msg("--plot %s: cannot run gnuplot: %s", out,
				strerror(-e));
	if (e)
		r = SH2000_EXIT_HELPER;
	else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
		r = report_failure(out, errfile, status);
	else
		r = SH2000_EXIT_OK;
out:
	unlink(script);
	unlink(errfile);
	return r;
}
