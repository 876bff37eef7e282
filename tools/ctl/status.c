/* SPDX-License-Identifier: MIT */
/* sh2000ctl info, status (table, JSON, watch) and dump. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <json-c/json.h>

#include "ctl.h"

#ifndef SH2000_TOOLS_VERSION
#define SH2000_TOOLS_VERSION "0.0.0"
#endif

static const char *backend_name(enum sh2000_backend_kind k)
{
	switch (k) {
	case SH2000_BACKEND_DEV:
		return "dev (kernel driver)";
	case SH2000_BACKEND_IO:
		return "io (direct port I/O)";
	case SH2000_BACKEND_SIM:
		return "sim (in-process card model, virtual time)";
	case SH2000_BACKEND_SHM:
		return "sim:NAME (served card model, real time)";
	case SH2000_BACKEND_PORTS:
		return "ports (a program's own register-level card)";
	}
	return "?";
}

static int get_global(struct ctl *c, unsigned int id, double *v)
{
	int r = sh2000_param_get(c->h, SH2000_GLOBAL, id, v);

	if (r < 0)
		return sh2000_tool_fail(c->h, r, "get parameter");
	return 0;
}

int ctl_info(struct ctl *c, int argc, char **argv)
{
	struct sh2000_port_counters pc;
	double coarse, fine, hto, sp, scale;
	unsigned int v;
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	if (argc > 1)
		return sh2000_tool_usage(argv[0], "info: unexpected '%s'", argv[1]);
	r = ctl_open(c);
	if (r)
		return r;
	v = sh2000_card_version(c->h);
	printf("device           %s\n", sh2000_device(c->h));
	printf("backend          %s\n", backend_name(sh2000_backend(c->h)));
	printf("card protocol    %u.%u\n", SH2000_PROTO_VERSION_MAJOR(v),
	       SH2000_PROTO_VERSION_MINOR(v));
	/* the library actually loaded, not the one the tool was built with */
	printf("library          libsh2000 %s (libsh2000.so.%u), protocol %u.%u\n",
	       sh2000_version(), sh2000_soversion(), SH2000_PROTO_MAJOR,
	       SH2000_PROTO_MINOR);
	if (sh2000_backend(c->h) == SH2000_BACKEND_DEV) {
		char dv[64];
		unsigned int abi, flags;

		if (sh2000_driver_info(c->h, dv, sizeof(dv), &abi, &flags) == 0)
			printf("driver           %s, ABI %u (library speaks %u)%s\n",
			       dv, abi, sh2000_driver_abi(),
			       (flags & SH2000_DRIVER_SIMULATED) ?
			       ", simulated card" : "");
	} else {
		printf("driver           not used (library speaks ABI %u)\n",
		       sh2000_driver_abi());
	}
	if ((r = get_global(c, SH2000_GP_COARSE_PERIOD_US, &coarse)) ||
	    (r = get_global(c, SH2000_GP_FINE_STEPS, &fine)) ||
	    (r = get_global(c, SH2000_GP_HOST_TIMEOUT_MS, &hto)) ||
	    (r = get_global(c, SH2000_GP_STATUS_PERIOD, &sp)))
		return r;
	printf("timing           coarse period %.0f us, %.0f fine steps, servo period %.3f us\n",
	       coarse, fine, coarse / fine);
	printf("host timeout     %.0f ms%s, status every %.0f servo cycles\n",
	       hto, hto == 0 ? " (off)" : "", sp);
	printf("scale            ");
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		r = sh2000_param_get(c->h, (int)a, SH2000_P_SCALE, &scale);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "get scale");
		printf("%s%c %g", a ? ", " : "", sh2000_tool_axis_name(a), scale);
	}
	printf(" counts/mm\n");
	r = sh2000_port_counters(c->h, &pc);
	if (r < 0)
		return sh2000_tool_fail(c->h, r, "port counters");
	printf("port cycles      %llu clears, %llu increments, %llu reads, %llu writes\n",
	       (unsigned long long)pc.clears,
	       (unsigned long long)pc.increments,
	       (unsigned long long)pc.data_reads,
	       (unsigned long long)pc.data_writes);
	return 0;
}

/* ---- status ------------------------------------------------------------ */

static void bits_text(char *buf, size_t len, unsigned int bits,
		      const char *(*name)(unsigned int))
{
	size_t n = 0;

	buf[0] = '\0';
	for (unsigned int b = 1; b && b <= 0x8000; b <<= 1)
		if (bits & b)
			n += (size_t)snprintf(buf + n, n < len ? len - n : 0,
					      "%s%s", n ? "," : "", name(b));
	if (!n)
		snprintf(buf, len, "-");
}

static const char *axis_state_name(unsigned int bit)
{
	switch (bit) {
	case SH2000_AXIS_ENABLED: return "enabled";
	case SH2000_AXIS_HOMED: return "homed";
	case SH2000_AXIS_HOMING: return "homing";
	case SH2000_AXIS_MOVING: return "moving";
	case SH2000_AXIS_LIMIT_POS: return "limit+";
	case SH2000_AXIS_LIMIT_NEG: return "limit-";
	case SH2000_AXIS_HOME_SW: return "home-switch";
	case SH2000_AXIS_INDEX: return "index";
	case SH2000_AXIS_INDEX_ARMED: return "index-armed";
	case SH2000_AXIS_INDEX_LATCHED: return "index-latched";
	}
	return "?";
}

static json_object *bits_json(unsigned int bits,
			      const char *(*name)(unsigned int))
{
	json_object *a = json_object_new_array();

	for (unsigned int b = 1; b && b <= 0x8000; b <<= 1)
		if (bits & b)
			json_object_array_add(a, json_object_new_string(name(b)));
	return a;
}

/* "axis Y limit switch" / "rejected" of the first-fault record. */
static void first_fault_text(char *buf, size_t n,
			     const struct sh2000_first_fault *ff)
{
	if (ff->axis < SH2000_AXES)
		snprintf(buf, n, "axis %c %s", sh2000_tool_axis_name(ff->axis),
			 sh2000_axis_fault_name(ff->bit));
	else
		snprintf(buf, n, "%s", sh2000_fault_name(ff->bit));
}

static void status_table(struct ctl *c, const struct sh2000_status *st,
			 const struct ctl_pair *pair)
{
	char f[256], s[256];

	bits_text(f, sizeof(f), st->card_faults, sh2000_fault_name);
	printf("device  %s\n", sh2000_device(c->h));
	printf("state   %s   faults %s   queue %u/%u   cycle %llu   heartbeat age %.3f ms\n",
	       sh2000_state_name(st->card_state), f, st->queue_fill,
	       st->queue_fill + st->queue_free,
	       (unsigned long long)st->card_cycle,
	       st->heartbeat_age_ns / 1e6);
	if (st->first_fault.bit) {
		first_fault_text(f, sizeof(f), &st->first_fault);
		printf("first fault: %s, cycle %llu\n", f,
		       (unsigned long long)st->first_fault.cycle);
	}
	if (st->reject_count)
		printf("last rejection: record %u, %s (%u so far)\n",
		       st->reject_seq, sh2000_reject_name(st->reject_reason),
		       st->reject_count);
	printf("axis  %14s %14s %11s %7s  %-24s %s\n", "position mm",
	       "set-point mm", "ferr mm", "dac", "state", "faults");
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_axis_status *ax = &st->axis[a];

		bits_text(s, sizeof(s), ax->state, axis_state_name);
		bits_text(f, sizeof(f), ax->faults, sh2000_axis_fault_name);
		printf("%-4c  %14.6f %14.6f %11.6f %7d  %-24s %s\n",
		       sh2000_tool_axis_name(a), ax->pos_mm, ax->cmd_mm,
		       ax->ferr_mm, ax->dac, s, f);
	}
	ctl_pair_print(pair);
}

/* null when none is known (nothing latched, or a card before 1.4) */
static json_object *first_fault_json(const struct sh2000_first_fault *ff)
{
	json_object *o;
	char n[2] = { 0, 0 };

	if (!ff->bit)
		return NULL;
	o = json_object_new_object();
	if (ff->axis < SH2000_AXES)
		n[0] = sh2000_tool_axis_name(ff->axis);
	json_object_object_add(o, "axis", n[0] ? json_object_new_string(n) : NULL);
	json_object_object_add(o, "fault", json_object_new_string(
		ff->axis < SH2000_AXES ? sh2000_axis_fault_name(ff->bit) :
					  sh2000_fault_name(ff->bit)));
	json_object_object_add(o, "bit", json_object_new_int((int)ff->bit));
	json_object_object_add(o, "cycle", json_object_new_int64((int64_t)ff->cycle));
	return o;
}

static void status_json(struct ctl *c, const struct sh2000_status *st,
			const struct ctl_pair *pair, const char *error)
{
	json_object *o = json_object_new_object();
	json_object *axes = json_object_new_array();

	json_object_object_add(o, "device",
			       json_object_new_string(sh2000_device(c->h)));
	json_object_object_add(o, "state",
			       json_object_new_string(sh2000_state_name(st->card_state)));
	json_object_object_add(o, "state_code", json_object_new_int((int)st->card_state));
	json_object_object_add(o, "faults", bits_json(st->card_faults, sh2000_fault_name));
	json_object_object_add(o, "fault_bits", json_object_new_int((int)st->card_faults));
	json_object_object_add(o, "faulted",
			       json_object_new_boolean(sh2000_status_faulted(st)));
	json_object_object_add(o, "error", error ? json_object_new_string(error) : NULL);
	json_object_object_add(o, "first_fault", first_fault_json(&st->first_fault));
	json_object_object_add(o, "queue_fill", json_object_new_int((int)st->queue_fill));
	json_object_object_add(o, "queue_free", json_object_new_int((int)st->queue_free));
	json_object_object_add(o, "card_cycle", json_object_new_int64((int64_t)st->card_cycle));
	json_object_object_add(o, "heartbeat_age_s",
			       json_object_new_double(st->heartbeat_age_ns / 1e9));
	json_object_object_add(o, "estop_req", json_object_new_int(st->estop_req));
	json_object_object_add(o, "estop_ack", json_object_new_int(st->estop_ack));
	json_object_object_add(o, "reject_count", json_object_new_int(st->reject_count));
	json_object_object_add(o, "reject_seq", json_object_new_int(st->reject_seq));
	json_object_object_add(o, "reject_reason",
			       json_object_new_string(sh2000_reject_name(st->reject_reason)));
	for (unsigned int a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_axis_status *ax = &st->axis[a];
		json_object *x = json_object_new_object();
		char n[2] = { sh2000_tool_axis_name(a), 0 };

		json_object_object_add(x, "axis", json_object_new_string(n));
		json_object_object_add(x, "enabled",
				       json_object_new_boolean(!!(ax->state & SH2000_AXIS_ENABLED)));
		json_object_object_add(x, "homed",
				       json_object_new_boolean(!!(ax->state & SH2000_AXIS_HOMED)));
		json_object_object_add(x, "pos_mm", json_object_new_double(ax->pos_mm));
		json_object_object_add(x, "cmd_mm", json_object_new_double(ax->cmd_mm));
		json_object_object_add(x, "ferr_mm", json_object_new_double(ax->ferr_mm));
		json_object_object_add(x, "pos_counts", json_object_new_int64(ax->pos_counts));
		json_object_object_add(x, "cmd_counts", json_object_new_int64(ax->cmd_counts));
		json_object_object_add(x, "dac", json_object_new_int(ax->dac));
		json_object_object_add(x, "state", bits_json(ax->state, axis_state_name));
		json_object_object_add(x, "faults", bits_json(ax->faults, sh2000_axis_fault_name));
		json_object_array_add(axes, x);
	}
	json_object_object_add(o, "axes", axes);
	json_object_object_add(o, "gantry", ctl_pair_json(pair));
	printf("%s\n", json_object_to_json_string_ext(o, JSON_C_TO_STRING_PLAIN |
						      JSON_C_TO_STRING_NOSLASHESCAPE));
	json_object_put(o);
}

/* The table's error line: the library's words without the device (the
 * table's first line names it) and without the code's summary, which
 * says the same again ("card stopped: ...: card stopped: ..."). */
static const char *table_error(struct ctl *c, int e, const char *err)
{
	const char *dev = sh2000_device(c->h);
	size_t n = strlen(dev);

	if (!err[0])
		return sh2000_strerror(e);
	if (!strncmp(err, dev, n) && !strncmp(err + n, ": ", 2))
		return err + n + 2;
	return err;
}

int ctl_status(struct ctl *c, int argc, char **argv)
{
	int json = 0, watch = 0, rc = 0;
	double interval = 1.0;
	long count = -1;

	if (ctl_want_help(argc, argv))
		return 0;
	for (int i = 1; i < argc; i++) {
		const char *v;
		int k;

		if (!strcmp(argv[i], "--json")) {
			json = 1;
			continue;
		}
		if (!strncmp(argv[i], "--watch", 7) &&
		    (argv[i][7] == '\0' || argv[i][7] == '=')) {
			watch = 1;
			v = argv[i][7] == '=' ? argv[i] + 8 :
			    (i + 1 < argc && !ctl_is_option(argv[i + 1])) ?
			    argv[++i] : NULL;
			if (v && (sh2000_tool_double(v, &interval) < 0 ||
				  interval < 0.01 || interval > 3600))
				return sh2000_tool_usage(argv[0],
					"status: --watch: '%s' is not an interval in seconds (0.01..3600)",
					v);
			continue;
		}
		k = ctl_opt_value(argc, argv, &i, "--count", 'n', &v);
		if (k < 0)
			return SH2000_EXIT_USAGE;
		if (k > 0) {
			if (sh2000_tool_long(v, 1, 1000000000L, &count) < 0)
				return sh2000_tool_usage(argv[0],
					"status: --count: '%s' is not a positive integer", v);
			continue;
		}
		return sh2000_tool_usage(argv[0], "status: unexpected '%s'", argv[i]);
	}
	if (count > 0 && !watch)
		return sh2000_tool_usage(argv[0], "status: --count needs --watch");
	rc = ctl_open(c);
	if (rc)
		return rc;
	if (watch)
		sh2000_tool_catch_stop(SH2000_SECOND_COUNTS);
	for (long n = 0; !(watch && sh2000_tool_stop_asked()); n++) {
		struct sh2000_status st;
		struct ctl_pair pair;
		char err[512] = "";
		int r = sh2000_poll(c->h, &st), e;

		if (r < 0)
			return sh2000_tool_fail(c->h, r, "status");
		r = ctl_pair_get(c, &st, &pair);
		if (r)
			return r;
		e = sh2000_status_error(c->h, &st);
		if (e < 0)
			sh2000_last_error_copy(c->h, err, sizeof(err));
		if (json) {
			status_json(c, &st, &pair, e < 0 ? err : NULL);
		} else {
			if (n)
				printf("\n");
			status_table(c, &st, &pair);
			if (e < 0)
				printf("error   %s\n", table_error(c, e, err));
		}
		fflush(stdout);
		rc = sh2000_tool_exit_code(e);
		if (!watch || (count > 0 && n + 1 >= count))
			break;
		/* a watch is for people: real time, and for `sim` the card's
		 * virtual time advances by the interval as well */
		{
			struct timespec ts = {
				.tv_sec = (time_t)interval,
				.tv_nsec = (long)((interval - floor(interval)) * 1e9),
			};

			if (sh2000_backend(c->h) == SH2000_BACKEND_SIM)
				sh2000_sleep_ns(c->h, (uint64_t)(interval * 1e9));
			nanosleep(&ts, NULL);
		}
	}
	return rc;
}

/* ---- dump -------------------------------------------------------------- */

static int parse_word(const char *s, size_t n, long *v)
{
	char buf[32];

	if (n == 0 || n >= sizeof(buf))
		return -1;
	memcpy(buf, s, n);
	buf[n] = '\0';
	return sh2000_tool_long(buf, 0, SH2000_DPRAM_WORDS - 1, v);
}

int ctl_dump(struct ctl *c, int argc, char **argv)
{
	unsigned int from[64], to[64], nr = 0;
	static uint16_t buf[SH2000_DPRAM_WORDS];
	int r;

	if (ctl_want_help(argc, argv))
		return 0;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *sep;
		long x, y;

		if (nr == 64)
			return sh2000_tool_usage(argv[0], "dump: at most 64 ranges");
		if (!strcmp(a, "all")) {
			from[nr] = 0;
			to[nr++] = SH2000_DPRAM_WORDS - 1;
			continue;
		}
		sep = strpbrk(a, "-+");
		if (!sep) {
			if (parse_word(a, strlen(a), &x) < 0)
				goto bad;
			from[nr] = to[nr] = (unsigned int)x;
			nr++;
			continue;
		}
		if (parse_word(a, (size_t)(sep - a), &x) < 0)
			goto bad;
		if (*sep == '-') {
			if (parse_word(sep + 1, strlen(sep + 1), &y) < 0 || y < x)
				goto bad;
		} else {
			long n;

			if (sh2000_tool_long(sep + 1, 1, SH2000_DPRAM_WORDS, &n) < 0 ||
			    x + n > SH2000_DPRAM_WORDS)
				goto bad;
			y = x + n - 1;
		}
		from[nr] = (unsigned int)x;
		to[nr++] = (unsigned int)y;
		continue;
bad:
		return sh2000_tool_usage(argv[0],
			"dump: bad range '%s' (N, N-M, N+COUNT or all; words 0..%u)",
			a, SH2000_DPRAM_WORDS - 1);
	}
	if (!nr) {
		from[0] = 0;
		to[nr++] = SH2000_DPRAM_WORDS - 1;
	}
	r = ctl_open(c);
	if (r)
		return r;
	for (unsigned int k = 0; k < nr; k++) {
		unsigned int n = to[k] - from[k] + 1;

		r = sh2000_ram_read(c->h, from[k], n, buf);
		if (r < 0)
			return sh2000_tool_fail(c->h, r, "dump");
		for (unsigned int w = 0; w < n; w++) {
			if (w % 8 == 0)
				printf("%s0x%03x:", w ? "\n" : "", from[k] + w);
			printf(" %04x", buf[w]);
		}
		printf("\n");
	}
	return 0;
}
