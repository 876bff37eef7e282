// SPDX-License-Identifier: MIT
/*
 * The program sh2000-upload runs: a reader over the file, or over what
 * LinuxCNC's rs274 made of it (--rs274), with its diagnostics.
 */
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "upload.h"

extern char **environ;

/* rs274 -g -t tool.tbl -v empty.var FILE > DIR/rs274.canon */
static int run_rs274(const char *file, struct upl_source *s)
{
	char tbl[128], var[128];
	char *argv[] = { "rs274", "-g", "-t", tbl, "-v", var, (char *)file,
			 NULL };
	posix_spawn_file_actions_t fa;
	int fd, e, status;
	pid_t pid;

	snprintf(s->dir, sizeof(s->dir), "/tmp/sh2000-rs274.XXXXXX");
	if (!mkdtemp(s->dir)) {
		sh2000_tool_msg("--rs274: temporary directory: %s",
				strerror(errno));
		s->dir[0] = 0;
		return SH2000_EXIT_CARD;
	}
	snprintf(tbl, sizeof(tbl), "%s/tool.tbl", s->dir);
	snprintf(var, sizeof(var), "%s/empty.var", s->dir);
	snprintf(s->canon, sizeof(s->canon), "%s/rs274.canon", s->dir);
	for (int i = 0; i < 2; i++) {
		fd = open(i ? var : tbl, O_WRONLY | O_CREAT | O_TRUNC, 0600);
		if (fd >= 0)
			close(fd);
	}
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
	posix_spawn_file_actions_addopen(&fa, 1, s->canon,
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

int upl_source_open(struct upl_source *s, const struct upl_opts *o,
		    const double start[SH2000_AXES])
{
	struct sh2000_prog_options po;
	int r, x;

	memset(s, 0, sizeof(*s));
	sh2000_prog_diags_init(&s->diags);
	sh2000_prog_options_default(&po);
	memcpy(po.start, start, sizeof(po.start));
	po.feed_mm_s = o->feed_mm_min / 60.0;
	if (o->rs274) {
		x = run_rs274(o->file, s);
		if (x)
			return x;
		r = sh2000_prog_reader_open(&s->reader, SH2000_PROG_CANON,
					    s->canon, &po, &s->diags);
	} else {
		r = sh2000_prog_reader_open(&s->reader, o->format, o->file,
					    &po, &s->diags);
	}
	if (!r)
		return SH2000_EXIT_OK;
	sh2000_prog_diags_print(&s->diags, stderr);
	if (r == -SH2000_PROG_EFORMAT)
		return sh2000_tool_usage(NULL,
			"%s: cannot tell the format from the name; use --format",
			o->file);
	/* the file cannot be read: an I/O error, not the program's */
	if (!s->diags.count)
		sh2000_tool_msg("%s: %s", o->file, sh2000_strerror(r));
	return SH2000_EXIT_CARD;
}

int upl_source_errors(struct upl_source *s, const struct upl_opts *o)
{
	sh2000_prog_diags_print(&s->diags, stderr);
	sh2000_tool_msg("%s: %zu error%s; nothing moved", o->file,
			s->diags.errors, s->diags.errors == 1 ? "" : "s");
	if (o->rs274) {
		/* the positions point into rs274's output */
		sh2000_tool_msg("--rs274: rs274's output is kept in %s",
				s->canon);
		s->dir[0] = 0;
	}
	return UPLOAD_EXIT_PROGRAM;
}

void upl_source_close(struct upl_source *s)
{
	sh2000_prog_reader_close(s->reader);
	s->reader = NULL;
	if (s->dir[0]) {
		unlink(s->canon);
		for (int i = 0; i < 2; i++) {
			char p[160];

			snprintf(p, sizeof(p), "%s/%s", s->dir,
				 i ? "empty.var" : "tool.tbl");
			unlink(p);
		}
		rmdir(s->dir);
		s->dir[0] = 0;
	}
	sh2000_prog_diags_free(&s->diags);
}
