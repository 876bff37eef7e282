// SPDX-License-Identifier: MIT
/* The planner's bookkeeping: its error message and its heap accounting
 * (sh2000_path_stats() reports mem_bytes and mem_peak). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "planner.h"

int pl_err(struct sh2000_path *p, int code, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(p->err, sizeof(p->err), fmt, ap);
	va_end(ap);
	return code;
}

void *pl_alloc(struct sh2000_path *p, size_t n)
{
	void *ptr = calloc(1, n ? n : 1);

	if (ptr) {
		p->mem += n;
		if (p->mem > p->mem_peak)
			p->mem_peak = p->mem;
	}
	return ptr;
}

void pl_free(struct sh2000_path *p, void *ptr, size_t n)
{
	if (!ptr)
		return;
	p->mem -= n;
	free(ptr);
}

const char *sh2000_path_error(const struct sh2000_path *p)
{
	return p->err;
}
