/* SPDX-License-Identifier: MIT */
/*
 * The parameter file of `sh2000ctl params load` read into a plan (the
 * format is in params_plan.h). Only reading and the checks that need no
 * card: unknown names, sections, numbers, repeats. Every problem is
 * reported with its line and counted; reading goes on to the end so one
 * run shows them all.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params_plan.h"

const char *ctl_plan_section(unsigned int s)
{
	static const char *const n[] = { "x", "y", "z", "a", "global" };

	return s <= CTL_SECT_GLOBAL ? n[s] : "?";
}

void ctl_plan_error(struct ctl_plan *p, int line, const char *fmt, ...)
{
	char msg[512];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (p->file)
		sh2000_tool_msg("%s:%d: %s", p->file, line, msg);
	else if (p->dev)
		sh2000_tool_msg("%s: params: %s", p->dev, msg);
	else
		sh2000_tool_msg("params: %s", msg);
	p->errors++;
}

void ctl_plan_add(struct ctl_plan *p, unsigned int s, const char *name,
		  const char *value, int line)
{
	int id = sh2000_param_id(name);
	double v;

	if (id < 0) {
		ctl_plan_error(p, line, "unknown parameter '%s'", name);
		return;
	}
	if ((s == CTL_SECT_GLOBAL) != (id >= SH2000_GP_FIRST)) {
		ctl_plan_error(p, line, "%s is %s parameter, not one of [%s]", name,
			   id >= SH2000_GP_FIRST ? "a global" : "an axis",
			   ctl_plan_section(s));
		return;
	}
	if (sh2000_tool_double(value, &v) < 0) {
		ctl_plan_error(p, line, "%s: '%s' is not a number", name, value);
		return;
	}
	if (p->set[s][id]) {
		if (p->file)
			ctl_plan_error(p, line, "%s of [%s] already set on line %d",
				   name, ctl_plan_section(s), p->line[s][id]);
		else
			ctl_plan_error(p, line, "%s given twice", name);
		return;
	}
	p->set[s][id] = 1;
	p->v[s][id] = v;
	p->line[s][id] = line;
}

static char *trim(char *s)
{
	char *e;

	while (*s == ' ' || *s == '\t')
		s++;
	e = s + strlen(s);
	while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' ||
			 e[-1] == '\n'))
		*--e = '\0';
	return s;
}

int ctl_plan_read(struct ctl_plan *p, FILE *f, const char *path)
{
	char *buf = NULL;
	size_t cap = 0;
	int line = 0, sect = -1;

	while (getline(&buf, &cap, f) >= 0) {
		char *s = buf, *eq, *c;

		line++;
		c = strpbrk(s, "#;");
		if (c)
			*c = '\0';
		s = trim(s);
		if (!*s)
			continue;
		if (*s == '[') {
			char *e = strchr(s, ']');
			int a;

			if (!e || e[1]) {
				ctl_plan_error(p, line, "bad section header '%s'", s);
				continue;
			}
			*e = '\0';
			s = trim(s + 1);
			a = sh2000_tool_axis(s);
			if (!strcmp(s, "global"))
				sect = CTL_SECT_GLOBAL;
			else if (a >= 0)
				sect = a;
			else {
				ctl_plan_error(p, line,
					   "unknown section [%s] (x, y, z, a or global)", s);
				sect = -2;
			}
			continue;
		}
		eq = strchr(s, '=');
		if (!eq) {
			ctl_plan_error(p, line, "expected 'name = value' or '[section]', got '%s'", s);
			continue;
		}
		*eq = '\0';
		if (sect == -1) {
			ctl_plan_error(p, line, "'%s' before any [section]", trim(s));
			continue;
		}
		if (sect == -2)
			continue;	/* already reported */
		ctl_plan_add(p, (unsigned int)sect, trim(s), trim(eq + 1), line);
	}
	if (ferror(f)) {
		sh2000_tool_msg("%s: read error: %s", path, strerror(errno));
		p->errors++;
	}
	free(buf);
	return p->errors ? -1 : 0;
}

