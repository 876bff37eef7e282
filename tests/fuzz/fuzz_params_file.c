// SPDX-License-Identifier: MIT
/*
 * The parameter-file reader of `sh2000ctl params load` (tools/ctl/
 * params_plan.c) on arbitrary text. Promises checked: it returns 0 or -1,
 * -1 exactly when it counted errors, each error is one message naming the
 * file and a line of it, and everything it accepted is a known parameter
 * of the right section with a finite value and the line it came from.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "params_plan.h"

/* The messages (sh2000_tool_msg writes to stderr, a plain variable in
 * glibc): one a line, each "sh2000: fuzz.params:LINE: ...". */
static void check_messages(const char *text, size_t len, int errors,
			   unsigned int lines)
{
	const char *p = text, *end = text + len;
	int n = 0;

	while (p < end) {
		const char *nl = memchr(p, '\n', (size_t)(end - p));
		unsigned int line;

		if (!nl)
			fz_fail("message without a newline: %.*s",
				(int)(end - p), p);
		if (sscanf(p, "sh2000: fuzz.params:%u: ", &line) != 1 ||
		    line < 1 || line > lines)
			fz_fail("message does not name a line: %.*s",
				(int)(nl - p), p);
		n++;
		p = nl + 1;
	}
	if (n != errors)
		fz_fail("%d messages for %d errors", n, errors);
}

static unsigned int count_lines(const uint8_t *data, size_t size)
{
	unsigned int n = 1;

	for (size_t i = 0; i < size; i++)
		n += data[i] == '\n';
	return n;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct ctl_plan *p = calloc(1, sizeof(*p));
	unsigned int lines = count_lines(data, size);
	FILE *f, *err, *saved = stderr;
	char *msgs = NULL;
	size_t msglen = 0;
	int r;

	if (!p)
		return 0;
	/* fmemopen of 0 bytes fails: an empty file is one empty line */
	f = fmemopen(size ? (void *)data : (void *)"", size ? size : 1, "r");
	if (!f)
		fz_fail("fmemopen failed");
	err = open_memstream(&msgs, &msglen);
	if (!err)
		fz_fail("open_memstream failed");
	p->file = "fuzz.params";
	stderr = err;
	r = ctl_plan_read(p, f, "fuzz.params");
	stderr = saved;
	fclose(f);
	fclose(err);
	check_messages(msgs, msglen, p->errors, lines);
	free(msgs);
	if (r != 0 && r != -1)
		fz_fail("ctl_plan_read returned %d", r);
	if ((r == -1) != (p->errors > 0))
		fz_fail("returned %d with %d errors", r, p->errors);
	for (unsigned int s = 0; s <= CTL_SECT_GLOBAL; s++)
		for (unsigned int id = 0; id < SH2000_GP_END; id++) {
			if (!p->set[s][id])
				continue;
			if (!sh2000_param_lookup(id) ||
			    (s == CTL_SECT_GLOBAL) != (id >= SH2000_GP_FIRST))
				fz_fail("[%s] holds parameter %u",
					ctl_plan_section(s), id);
			if (!isfinite(p->v[s][id]))
				fz_fail("[%s] %s = %g", ctl_plan_section(s),
					sh2000_param_name(id), p->v[s][id]);
			if (p->line[s][id] < 1 ||
			    (unsigned int)p->line[s][id] > lines)
				fz_fail("[%s] %s from line %d of %u",
					ctl_plan_section(s),
					sh2000_param_name(id), p->line[s][id],
					lines);
		}
	free(p);
	return 0;
}
