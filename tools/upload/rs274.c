// SPDX-License-Identifier: MIT
/*
 * --rs274: LinuxCNC's standalone interpreter run on the program, with the
 * tool table and parameter file it is given made from sh2000-upload's
 * (in the interpreter's units), its output read by the canonical reader.
 */
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "upload.h"

extern char **environ;

/* What --rs274 keeps in its temporary directory (rs274 saves the
 * parameters it ends with over its -v file, the old one as .bak). */
static const char *const rs274_files[] = {
	"tool.tbl", "params.var", "params.var.bak", "rs274.canon",
	".tool.mmap",
};

/* rs274's environment: ours with home ("HOME=its own directory") for
 * HOME. LinuxCNC's interpreter keeps its tool data in $HOME/.tool.mmap,
 * which it creates truncated: two rs274 at once with the same HOME (two
 * uploads, a dry run beside a run) die of SIGBUS in about one run in
 * fifteen. NULL when out of memory; free() it. */
static char **rs274_env(char *home)
{
	size_t n = 0, k = 0;
	char **env;

	while (environ[n])
		n++;
	env = calloc(n + 2, sizeof(*env));
	if (!env)
		return NULL;
	for (size_t i = 0; i < n; i++)
		if (strncmp(environ[i], "HOME=", 5))
			env[k++] = environ[i];
	env[k] = home;
	return env;
}

/* The tool table as rs274 reads it. The standalone interpreter's machine
 * units are inches (a table's Z+1 is an inch to it, in a G21 program
 * too), the table's are mm as on a LinuxCNC machine in mm: its lengths go
 * over divided by 25.4. A stays as it is: rs274 never scales A, an angle
 * to LinuxCNC and a length in mm on this card. */
static int write_rs274_table(const char *path,
			     const struct sh2000_tool_table *t)
{
	FILE *f = fopen(path, "w");
	int e;

	if (!f)
		return -errno;
	for (size_t i = 0; i < t->count; i++) {
		const struct sh2000_tool *k = &t->tools[i];

		fprintf(f, "T%d P%d X%.12g Y%.12g Z%.12g A%.12g D%.12g I%.12g J%.12g Q%d\n",
			k->number, k->pocket, k->offset[0] / 25.4,
			k->offset[1] / 25.4, k->offset[2] / 25.4, k->offset[3],
			k->diameter / 25.4, k->front_angle, k->back_angle,
			k->orientation);
	}
	e = ferror(f) ? -EIO : 0;
	if (fclose(f) && !e)
		e = -errno;
	return e;
}

/* A length among LinuxCNC's persistent parameters: the X Y Z and U V W
 * slots of G28 (5161..), G30 (5181..), G92 (5211..) and the nine
 * coordinate systems G54..G59.3 (5221.., 20 apart). A B C are angles to
 * LinuxCNC (and rs274 leaves A unscaled), the rest are numbers. */
static bool length_parameter(long n)
{
	long base = n >= 5221 && n < 5221 + 9 * 20 ? 5221 + (n - 5221) / 20 * 20 :
		    n >= 5211 && n < 5220 ? 5211 :
		    n >= 5181 && n < 5190 ? 5181 :
		    n >= 5161 && n < 5170 ? 5161 : -1;
	long k = n - base;

	return base > 0 && (k <= 2 || (k >= 6 && k <= 8));
}

/* rs274's parameter file: --parameter-file's (the machine's, in mm, as a
 * LinuxCNC machine in mm keeps it) with its lengths in rs274's inches;
 * other lines as they are. Empty without the option. rs274 rewrites its
 * copy at the end; the user's stays as it was. */
static int write_rs274_params(const char *path, const char *from)
{
	FILE *in = from ? fopen(from, "r") : NULL, *out;
	char line[1024];
	int e = 0;

	if (from && !in)
		return -errno;
	out = fopen(path, "w");
	if (!out)
		e = -errno;
	while (!e && in && fgets(line, sizeof(line), in)) {
		char *end;
		long n = strtol(line, &end, 10);
		double v;

		if (end != line && length_parameter(n) &&
		    sscanf(end, "%lf", &v) == 1)
			fprintf(out, "%ld\t%.12g\n", n, v / 25.4);
		else
			fputs(line, out);
	}
	if (in && ferror(in))
		e = -EIO;
	if (in)
		fclose(in);
	if (out && (ferror(out) | fclose(out)) && !e)
		e = -EIO;
	return e;
}

/* The table and the parameters rs274 is given; 0 or an exit code. */
static int rs274_inputs(const struct upl_opts *o, struct upl_source *s,
			const char *tbl, const char *var)
{
	int e = write_rs274_table(tbl, &s->tools);

	if (e) {
		sh2000_tool_msg("--rs274: %s: %s", tbl, strerror(-e));
		return SH2000_EXIT_CARD;
	}
	e = write_rs274_params(var, o->parameter_file);
	if (e) {
		sh2000_tool_msg("%s%s: %s",
				o->parameter_file ? "--parameter-file " : "--rs274: ",
				o->parameter_file ? o->parameter_file : var,
				strerror(-e));
		return SH2000_EXIT_CARD;
	}
	return SH2000_EXIT_OK;
}

int upl_rs274_run(const struct upl_opts *o, struct upl_source *s)
{
	char tbl[128], var[128], home[sizeof(s->dir) + 5];
	char *argv[] = { "rs274", "-g", "-t", tbl, "-v", var, (char *)o->file,
			 NULL };
	posix_spawn_file_actions_t fa;
	int e, status, x;
	char **env;
	pid_t pid;

	snprintf(s->dir, sizeof(s->dir), "/tmp/sh2000-rs274.XXXXXX");
	if (!mkdtemp(s->dir)) {
		sh2000_tool_msg("--rs274: temporary directory: %s",
				strerror(errno));
		s->dir[0] = 0;
		return SH2000_EXIT_CARD;
	}
	snprintf(tbl, sizeof(tbl), "%s/%s", s->dir, rs274_files[0]);
	snprintf(var, sizeof(var), "%s/%s", s->dir, rs274_files[1]);
	snprintf(s->canon, sizeof(s->canon), "%s/%s", s->dir, rs274_files[3]);
	x = rs274_inputs(o, s, tbl, var);
	if (x)
		return x;
	snprintf(home, sizeof(home), "HOME=%s", s->dir);
	env = rs274_env(home);
	if (!env) {
		sh2000_tool_msg("--rs274: %s", strerror(ENOMEM));
		return SH2000_EXIT_HELPER;
	}
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
	posix_spawn_file_actions_addopen(&fa, 1, s->canon,
					 O_WRONLY | O_CREAT | O_TRUNC, 0600);
	e = posix_spawnp(&pid, "rs274", &fa, NULL, argv, env);
	posix_spawn_file_actions_destroy(&fa);
	free(env);
	if (e) {
		sh2000_tool_msg("--rs274: cannot run rs274: %s", strerror(e));
		return SH2000_EXIT_HELPER;
	}
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR)
			return SH2000_EXIT_HELPER;
	/* rs274 stops printing at an error; the reader then finds no
	 * PROGRAM_END and says so, after rs274's own message */
	if (!WIFEXITED(status))
		sh2000_tool_msg("--rs274: rs274 ended by signal %d",
				WTERMSIG(status));
	return SH2000_EXIT_OK;
}

void upl_rs274_clean(struct upl_source *s)
{
	if (!s->dir[0])
		return;
	for (size_t i = 0; i < sizeof(rs274_files) / sizeof(rs274_files[0]);
	     i++) {
		char p[160];

		snprintf(p, sizeof(p), "%s/%s", s->dir, rs274_files[i]);
		unlink(p);
	}
	rmdir(s->dir);
	s->dir[0] = 0;
}
