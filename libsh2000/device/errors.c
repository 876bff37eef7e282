/* SPDX-License-Identifier: MIT */
/* The error rule: negative codes, their names and per-handle details. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "sh2000_internal.h"

static const char *const sh2000_errnames[SH2000_E_LAST - SH2000_E_BASE + 1] = {
	[SH2000_EVERSION - SH2000_E_BASE] = "card speaks another protocol version",
	[SH2000_EMAGIC - SH2000_E_BASE] = "no firmware: card magic word wrong",
	[SH2000_EHEARTBEAT - SH2000_E_BASE] = "card heartbeat stopped (DSP not running)",
	[SH2000_ETIMEOUT - SH2000_E_BASE] = "timed out waiting for the card",
	[SH2000_EQUEUE_FULL - SH2000_E_BASE] = "segment queue has no room for the batch",
	[SH2000_EPARAM - SH2000_E_BASE] = "bad parameter value",
	[SH2000_ETORN - SH2000_E_BASE] = "status snapshot kept tearing",
	[SH2000_ENOTSIM - SH2000_E_BASE] = "not a simulated card",
	[SH2000_ESTOPPED - SH2000_E_BASE] = "card stopped the motion (a STOP command)",
	[SH2000_EOWNED - SH2000_E_BASE] = "another program controls the motion",
	[SH2000_ECMD_OP - SH2000_E_BASE] = "card rejected the command: unknown operation",
	[SH2000_ECMD_AXIS - SH2000_E_BASE] = "card rejected the command: bad axis",
	[SH2000_ECMD_PARAM - SH2000_E_BASE] = "card rejected the command: unknown parameter",
	[SH2000_ECMD_VALUE - SH2000_E_BASE] = "card rejected the command: value out of range",
	[SH2000_ECMD_BUSY - SH2000_E_BASE] = "card rejected the command: busy moving",
	[SH2000_ECMD_FAULTED - SH2000_E_BASE] = "card rejected the command: fault latched",
	[SH2000_ECMD_CHECKSUM - SH2000_E_BASE] = "card rejected the command: check word wrong",
	[SH2000_ECMD_DISABLED - SH2000_E_BASE] = "card rejected the command: axis not enabled or not idle",
	[SH2000_ECMD_UNKNOWN - SH2000_E_BASE] = "card answered an unknown result code",
	[SH2000_EESTOP - SH2000_E_BASE] = "emergency stop latched",
	[SH2000_EUNDERRUN - SH2000_E_BASE] = "segment queue ran dry during motion",
	[SH2000_EHOST_TIMEOUT - SH2000_E_BASE] = "card stopped: host heartbeat timed out",
	[SH2000_EREJECTED - SH2000_E_BASE] = "card rejected a segment",
	[SH2000_EPROTOCOL - SH2000_E_BASE] = "card saw a protocol violation",
	[SH2000_EFAULTED - SH2000_E_BASE] = "card faulted",
	[SH2000_EFERR - SH2000_E_BASE] = "axis following error limit exceeded",
	[SH2000_ESOFT_LIMIT - SH2000_E_BASE] = "axis beyond a soft limit",
	[SH2000_EHARD_LIMIT - SH2000_E_BASE] = "axis hit a limit switch",
	[SH2000_EDAC_SAT - SH2000_E_BASE] = "axis DAC saturated",
	[SH2000_ECOUNTER - SH2000_E_BASE] = "axis encoder counter fault",
	[SH2000_EHOME - SH2000_E_BASE] = "axis homing failed",
	[SH2000_ESKEW - SH2000_E_BASE] = "gantry pair skew limit exceeded",
	[SH2000_EPROGRAM - SH2000_E_BASE] = "the program has errors",
	[SH2000_EFORMAT - SH2000_E_BASE] = "unknown program format",
	[SH2000_ELIMIT - SH2000_E_BASE] = "planned motion beyond a soft limit",
	[SH2000_EMOVED - SH2000_E_BASE] = "the card moved since the program was checked",
	[SH2000_EGANTRY - SH2000_E_BASE] = "a motion moves a gantry pair's sides apart",
	[SH2000_EGATHER_CHECK - SH2000_E_BASE] = "gathered data kept failing its check word",
	[SH2000_EGATHER_LOST - SH2000_E_BASE] = "the gathered record was replaced by a new one",
};

const char *sh2000_strerror(int code)
{
	int e = -code;

	if (code >= 0)
		return "success";
	if (e >= SH2000_E_BASE && e <= SH2000_E_LAST) {
		const char *s = sh2000_errnames[e - SH2000_E_BASE];

		return s ? s : "unknown libsh2000 error";
	}
	if (e < SH2000_E_BASE) {
		/* strerrordesc_np: the thread-safe, locale-free name */
		const char *s = strerrordesc_np(e);

		return s ? s : "unknown system error";
	}
	return "unknown error";
}

int sh2000_fail(struct sh2000 *h, int code, const char *fmt, ...)
{
	va_list ap;
	int n;

	if (!h)
		return code;
	n = snprintf(h->err, sizeof(h->err), "%s: ", h->device);
	if (n < 0 || (size_t)n >= sizeof(h->err))
		n = 0;
	va_start(ap, fmt);
	vsnprintf(h->err + n, sizeof(h->err) - (size_t)n, fmt, ap);
	va_end(ap);
	return code;
}

/* A feature a later protocol minor added, asked of an older card: refused
 * before a word is written, both versions named. */
int sh2000_need_minor(struct sh2000 *h, unsigned int minor, const char *what)
{
	if (SH2000_PROTO_VERSION_MINOR(h->card_version) >= minor)
		return 0;
	return sh2000_fail(h, -EOPNOTSUPP,
			   "the card speaks protocol %u.%u: %s 1.%u",
			   SH2000_PROTO_VERSION_MAJOR(h->card_version),
			   SH2000_PROTO_VERSION_MINOR(h->card_version), what,
			   minor);
}

int sh2000_msg(char *msg, size_t len, int code, const char *fmt, ...)
{
	va_list ap;

	if (!msg || !len)
		return code;
	va_start(ap, fmt);
	vsnprintf(msg, len, fmt, ap);
	va_end(ap);
	return code;
}

const char *sh2000_last_error(struct sh2000 *h)
{
	return h ? h->err : "no handle";
}

void sh2000_last_error_copy(struct sh2000 *h, char *buf, size_t len)
{
	if (!buf || !len)
		return;
	if (!h) {
		snprintf(buf, len, "no handle");
		return;
	}
	pthread_mutex_lock(&h->lock);
	snprintf(buf, len, "%s", h->err);
	pthread_mutex_unlock(&h->lock);
}

char sh2000_axis_letter(int axis)
{
	if (axis < 0 || axis >= (int)SH2000_AXES)
		return '?';
	return (char)tolower((unsigned char)SH2000_AXIS_LETTERS[axis]);
}
