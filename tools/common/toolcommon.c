/* SPDX-License-Identifier: MIT */
/* Shared code of the SH-2000 tools; see toolcommon.h. */
#include "toolcommon.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


static const char *tool_name = "sh2000";

void sh2000_tool_init(const char *name)
{
	if (name && *name)
		tool_name = name;
}

const char *sh2000_tool_name(void)
{
	return tool_name;
}

void sh2000_tool_vmsg(const char *fmt, va_list ap)
{
	fprintf(stderr, "%s: ", tool_name);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
}

void sh2000_tool_msg(const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	sh2000_tool_vmsg(fmt, ap);
	va_end(ap);
}

int sh2000_tool_usage(const char *sub, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	sh2000_tool_vmsg(fmt, ap);
	va_end(ap);
	if (sub)
		fprintf(stderr, "Try '%s %s --help'.\n", tool_name, sub);
	else
		fprintf(stderr, "Try '%s --help'.\n", tool_name);
	return SH2000_EXIT_USAGE;
}

const char *sh2000_tool_device(const char *arg)
{
	const char *env;

	if (arg && *arg)
		return arg;
	env = getenv(SH2000_DEVICE_ENV);
	if (env && *env)
		return env;
	return SH2000_DEFAULT_DEVICE;
}

int sh2000_tool_open(struct sh2000 **h, const char *device_arg)
{
	const char *dev = sh2000_tool_device(device_arg);
	char msg[512];
	int r;

	msg[0] = '\0';
	r = sh2000_open(h, dev, msg, sizeof(msg));
	if (r < 0) {
		/* the library's message names the device; make sure of it */
		if (msg[0] && !strncmp(msg, dev, strlen(dev)))
			sh2000_tool_msg("%s", msg);
		else if (msg[0])
			sh2000_tool_msg("%s: %s", dev, msg);
		else
			sh2000_tool_msg("%s: %s", dev, sh2000_strerror(r));
		*h = NULL;
		return SH2000_EXIT_DEVICE;
	}
	return SH2000_EXIT_OK;
}

int sh2000_tool_exit_code(int code)
{
	if (code >= 0)
		return SH2000_EXIT_OK;
	if ((code <= -SH2000_EESTOP && code >= -SH2000_ESKEW) ||
	    code == -SH2000_ECMD_FAULTED)
		return SH2000_EXIT_FAULT;
	return SH2000_EXIT_CARD;
}

int sh2000_tool_fail(struct sh2000 *h, int code, const char *what)
{
	const char *dev = h ? sh2000_device(h) : "?";
	char detail[512];
	const char *d = detail;
	size_t wn = what ? strlen(what) : 0;

	detail[0] = '\0';
	if (h)
		sh2000_last_error_copy(h, detail, sizeof(detail));
	if (!detail[0])
		snprintf(detail, sizeof(detail), "%s", sh2000_strerror(code));
	if (!strncmp(d, dev, strlen(dev)) && !strncmp(d + strlen(dev), ": ", 2))
		d += strlen(dev) + 2;
	/* the library's reason may name the call already ("home: the
	 * motion is held by ..."): one prefix, not two */
	if (wn && !strncmp(d, what, wn) && !strncmp(d + wn, ": ", 2))
		what = NULL;
	/* a card that stopped answering is not about the call that found it
	 * ("get parameter: card heartbeat stuck"): the reason alone */
	if (code == -SH2000_EHEARTBEAT || code == -SH2000_EMAGIC)
		what = NULL;
	sh2000_tool_msg("%s: %s%s%s", dev, what ? what : "", what ? ": " : "", d);
	return sh2000_tool_exit_code(code);
}

int sh2000_tool_axis(const char *s)
{
	if (!s || !s[0] || s[1])
		return -1;
	if (s[0] >= '0' && s[0] < '0' + (int)SH2000_AXES)
		return s[0] - '0';
	for (unsigned int i = 0; i < SH2000_AXES; i++)
		if (toupper((unsigned char)s[0]) == SH2000_AXIS_LETTERS[i])
			return (int)i;
	return -1;
}

char sh2000_tool_axis_name(unsigned int axis)
{
	return axis < SH2000_AXES ? (char)tolower(SH2000_AXIS_LETTERS[axis]) : '?';
}

int sh2000_tool_axes(const char *s)
{
	int mask = 0;

	if (!s || !*s)
		return -1;
	if (!strcasecmp(s, "all"))
		return 0xf;
	for (; *s; s++) {
		char one[2] = { *s, 0 };
		int a;

		if (*s == ',')
			continue;
		a = sh2000_tool_axis(one);
		if (a < 0)
			return -1;
		mask |= 1 << a;
	}
	return mask ? mask : -1;
}

int sh2000_tool_double(const char *s, double *v)
{
	char *end;
	double d;

	if (!s || !*s || isspace((unsigned char)*s))
		return -1;
	errno = 0;
	d = strtod(s, &end);
	if (*end || errno || !isfinite(d))
		return -1;
	*v = d;
	return 0;
}

int sh2000_tool_long(const char *s, long min, long max, long *v)
{
	char *end;
	long l;

	if (!s || !*s || isspace((unsigned char)*s))
		return -1;
	errno = 0;
	l = strtol(s, &end, 0);
	if (*end || errno || l < min || l > max)
		return -1;
	*v = l;
	return 0;
}

void sh2000_tool_print_version(const char *tool_version)
{
	printf("%s %s\n"
	       "libsh2000 %s (libsh2000.so.%u)\n"
	       "protocol %u.%u\n"
	       "driver ABI %u\n",
	       sh2000_tool_name(), tool_version, sh2000_version(),
	       sh2000_soversion(), SH2000_PROTO_MAJOR, SH2000_PROTO_MINOR,
	       sh2000_driver_abi());
}

int sh2000_tool_write_text(const char *path, const char *text, size_t len)
{
	FILE *f = strcmp(path, "-") ? fopen(path, "w") : stdout;
	int r = SH2000_EXIT_OK;

	if (!f) {
		sh2000_tool_msg("%s: cannot create: %s", path, strerror(errno));
		return SH2000_EXIT_CARD;
	}
	if (fwrite(text, 1, len, f) != len)
		r = SH2000_EXIT_CARD;
	if (f != stdout) {
		if (fclose(f) != 0)
			r = SH2000_EXIT_CARD;
	} else if (fflush(f) != 0) {
		r = SH2000_EXIT_CARD;
	}
	if (r) {
		sh2000_tool_msg("%s: write error: %s", path, strerror(errno));
		if (f != stdout)
			remove(path);
	}
	return r;
}
