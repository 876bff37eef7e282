/* SPDX-License-Identifier: MIT */
/*
 * The card's five loop gains of one axis (read by freqresp.c's
 * tune_read_gains()): written all or none (a set that fails puts the ones
 * already written back), and saved as a parameter file section through the tools' shared writer (paramfile.c),
 * so `sh2000ctl params load` reads it as it reads its own files.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "autotune.h"
#include "toolcommon.h"

static const unsigned int ids[] = {
	SH2000_P_KP, SH2000_P_TI, SH2000_P_TD, SH2000_P_KVFF, SH2000_P_KAFF,
};
#define NGAINS (sizeof(ids) / sizeof(ids[0]))

static double *field(struct tune_gains *g, unsigned int i)
{
	double *f[NGAINS] = { &g->kp, &g->ti, &g->td, &g->kvff, &g->kaff };

	return f[i];
}

int tune_gains_set(struct sh2000 *h, unsigned int a,
		   const struct tune_gains *gn, const struct tune_gains *old,
		   char *why, size_t whylen)
{
	struct tune_gains n = *gn, o = *old;

	for (unsigned int i = 0; i < NGAINS; i++) {
		int r = sh2000_param_set(h, (int)a, ids[i], *field(&n, i));

		if (r < 0) {
			/* the error's message first: the way back must not
			 * replace it */
			sh2000_last_error_copy(h, why, whylen);
			if (!why[0])
				snprintf(why, whylen, "%s", sh2000_strerror(r));
			for (unsigned int k = 0; k < i; k++)
				sh2000_param_set(h, (int)a, ids[k], *field(&o, k));
			return r;
		}
	}
	return 0;
}

int tune_gains_save(const char *path, const char *device, unsigned int a,
		    const struct tune_gains *gn)
{
	struct tune_gains g = *gn;
	char *text = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&text, &len);
	int r;

	if (!m) {
		sh2000_tool_msg("--save %s: %s", path, strerror(errno));
		return SH2000_EXIT_CARD;
	}
	fprintf(m, "# SH-2000 loop gains of axis %c of %s (sh2000-tune --auto)\n"
		   "# load with: sh2000ctl params load FILE\n\n[%c]\n",
		sh2000_tool_axis_name(a), device, sh2000_tool_axis_name(a));
	for (unsigned int i = 0; i < NGAINS; i++)
		sh2000_tool_param_line(m, ids[i], *field(&g, i));
	fclose(m);
	r = sh2000_tool_write_text(path, text, len);
	free(text);
	return r;
}
