// SPDX-License-Identifier: MIT
/*
 * The parameter table of protocol v1 and the names of states, results and
 * reasons. Host validation and card acceptance both use this table, so a
 * value the library accepts is a value the card accepts.
 *
 * Defaults describe the card model's default axis (docs/cardmodel.md): a
 * 2 kg linear motor on a 10 nm scale, +-10 V DAC.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "sh2000/sh2000_protocol.h"

#define I32_MIN (-2147483648.0)
#define I32_MAX 2147483647.0
/* the last column: taken while the card moves, or refused (BUSY) */
#define LIVE 1
#define FIXED 0

static const struct sh2000_param_info axis_params[SH2000_AXIS_PARAMS] = {
	{ SH2000_P_SCALE, "scale", SH2000_PT_F32, 0.0, 1e8, 1, 100000.0, FIXED },
	{ SH2000_P_KP, "kp", SH2000_PT_F32, 0.0, 1000.0, 0, 0.5, LIVE },
	{ SH2000_P_TI, "ti", SH2000_PT_F32, 0.0, 100.0, 0, 0.02, LIVE },
	{ SH2000_P_TD, "td", SH2000_PT_F32, 0.0, 10.0, 0, 0.004, LIVE },
	{ SH2000_P_KVFF, "kvff", SH2000_PT_F32, 0.0, 1.0, 0, 3.2768e-5, LIVE },
	{ SH2000_P_KAFF, "kaff", SH2000_PT_F32, 0.0, 1.0, 0, 3.2768e-6, LIVE },
	{ SH2000_P_DAC_RANGE, "dac_range", SH2000_PT_I32, 0.0, 3.0, 0,
	  SH2000_DAC_PM10V, FIXED },
	{ SH2000_P_DAC_LIMIT, "dac_limit", SH2000_PT_I32, 1.0, 32767.0, 0,
	  32767.0, FIXED },
	{ SH2000_P_FERR_LIMIT, "ferr_limit", SH2000_PT_I32, 0.0, 134217727.0,
	  1, 20000.0, LIVE },
	{ SH2000_P_SOFT_MIN, "soft_min", SH2000_PT_I32, I32_MIN, I32_MAX, 0,
	  I32_MIN, FIXED },
	{ SH2000_P_SOFT_MAX, "soft_max", SH2000_PT_I32, I32_MIN, I32_MAX, 0,
	  I32_MAX, FIXED },
	{ SH2000_P_VMAX, "vmax", SH2000_PT_F32, 0.0, 1e9, 1, 4e7, FIXED },
	{ SH2000_P_AMAX, "amax", SH2000_PT_F32, 0.0, 1e11, 1, 5e8, FIXED },
	{ SH2000_P_HOME_VEL, "home_vel", SH2000_PT_F32, -1e9, 1e9, 0, -2e6, FIXED },
	{ SH2000_P_HOME_DEBOUNCE, "home_debounce", SH2000_PT_I32, 1.0, 1000.0,
	  0, 10.0, FIXED },
	{ SH2000_P_HOME_OFFSET, "home_offset", SH2000_PT_I32, I32_MIN, I32_MAX,
	  0, 0.0, FIXED },
};

static const struct sh2000_param_info global_params[SH2000_GP_END -
						     SH2000_GP_FIRST] = {
	{ SH2000_GP_COARSE_PERIOD_US, "coarse_period_us", SH2000_PT_I32, 100.0,
	  100000.0, 0, 2000.0, FIXED },
	{ SH2000_GP_FINE_STEPS, "fine_steps", SH2000_PT_I32, 1.0, 1000.0, 0,
	  20.0, FIXED },
	{ SH2000_GP_HOST_TIMEOUT_MS, "host_timeout_ms", SH2000_PT_I32, 0.0,
	  60000.0, 0, 100.0, LIVE },
	{ SH2000_GP_STATUS_PERIOD, "status_period", SH2000_PT_I32, 1.0,
	  1000.0, 0, 10.0, LIVE },
	{ SH2000_GP_TIME_SCALE, "time_scale", SH2000_PT_I32, 0.0,
	  SH2000_TIME_SCALE_FULL, 0, SH2000_TIME_SCALE_FULL, LIVE },
	{ SH2000_GP_TIME_RAMP_MS, "time_ramp_ms", SH2000_PT_I32, 1.0,
	  60000.0, 0, 100.0, LIVE },
	/* protocol 1.7: the gantry pair. Pair and squaring change what the
	 * axes are: at rest only; the loop's gains and the limit are live. */
	{ SH2000_GP_GANTRY_PAIR, "gantry_pair", SH2000_PT_I32, 0.0,
	  0xc, 0, 0.0, FIXED },	/* the largest pair: the top two axes */
	{ SH2000_GP_GANTRY_KP, "gantry_kp", SH2000_PT_F32, 0.0, 1000.0, 0,
	  0.0, LIVE },
	{ SH2000_GP_GANTRY_TI, "gantry_ti", SH2000_PT_F32, 0.0, 100.0, 0,
	  0.0, LIVE },
	{ SH2000_GP_GANTRY_TD, "gantry_td", SH2000_PT_F32, 0.0, 10.0, 0,
	  0.0, LIVE },
	{ SH2000_GP_GANTRY_SKEW_LIMIT, "gantry_skew_limit", SH2000_PT_I32,
	  0.0, 134217727.0, 1, 10000.0, LIVE },
	{ SH2000_GP_GANTRY_SQUARE, "gantry_square", SH2000_PT_I32, -134217727.0,
	  134217727.0, 0, 0.0, FIXED },
};

const struct sh2000_param_info *sh2000_param_lookup(unsigned int id)
{
	if (id < SH2000_AXIS_PARAMS)
		return &axis_params[id];
	if (id >= SH2000_GP_FIRST && id < SH2000_GP_END)
		return &global_params[id - SH2000_GP_FIRST];
	return NULL;
}

unsigned int sh2000_param_since_minor(unsigned int id)
{
	if (id == SH2000_GP_TIME_SCALE || id == SH2000_GP_TIME_RAMP_MS)
		return SH2000_PROTO_MINOR_TIME_BASE;
	if (id >= SH2000_GP_GANTRY_PAIR && id <= SH2000_GP_GANTRY_SQUARE)
		return SH2000_PROTO_MINOR_GANTRY;
	return 0;
}

const struct sh2000_param_info *sh2000_param_by_name(const char *name)
{
	unsigned int i;

	if (!name)
		return NULL;
	for (i = 0; i < SH2000_AXIS_PARAMS; i++)
		if (!strcmp(axis_params[i].name, name))
			return &axis_params[i];
	for (i = 0; i < SH2000_GP_END - SH2000_GP_FIRST; i++)
		if (!strcmp(global_params[i].name, name))
			return &global_params[i];
	return NULL;
}

const char *sh2000_param_live_names(char *buf, size_t len)
{
	size_t n = 0;
	unsigned int id;

	if (!len)
		return buf;
	buf[0] = 0;
	for (id = 0; id < SH2000_GP_END; id++) {
		const struct sh2000_param_info *p = sh2000_param_lookup(id);
		int w;

		if (!p || !p->live)
			continue;
		w = snprintf(buf + n, len - n, "%s%s", n ? " " : "", p->name);
		if (w < 0 || (size_t)w >= len - n)
			break;
		n += (size_t)w;
	}
	return buf;
}

int sh2000_timing_ok(long long coarse_us, long long fine_steps)
{
	long long ns = coarse_us * 1000;

	return coarse_us > 0 && fine_steps > 0 && ns % fine_steps == 0 &&
	       ns / fine_steps >= (long long)SH2000_FW_MIN_SERVO_NS;
}

int sh2000_state_moving(unsigned int state)
{
	return state == SH2000_STATE_RUNNING ||
	       state == SH2000_STATE_STOPPING ||
	       state == SH2000_STATE_HOMING;
}

int sh2000_param_in_range(const struct sh2000_param_info *p, double v)
{
	if (!p || !isfinite(v))
		return -1;
	if (p->type == SH2000_PT_I32 && v != floor(v))
		return -1;
	if (p->type == SH2000_PT_F32 && v != 0.0 &&
	    (fabs(v) > 3.4028234663852886e38 || fabs(v) < 1.17549435e-38))
		return -1;	/* not a normal binary32 */
	if (p->min_exclusive ? !(v > p->min) : !(v >= p->min))
		return -1;
	if (!(v <= p->max))
		return -1;
	if (p->id == SH2000_P_HOME_VEL && v == 0.0)
		return -1;
	/* a pair is two axes: no axis (0), or exactly two bits */
	if (p->id == SH2000_GP_GANTRY_PAIR && v != 0.0 &&
	    __builtin_popcount((unsigned int)v) != 2)
		return -1;
	return 0;
}

/* Protocol 1.2: the signals a card records (section 17). */
static const struct sh2000_gather_signal_info gather_signals[] = {
	{ SH2000_GS_SETPOINT, "setpoint", SH2000_PT_I32, "counts" },
	{ SH2000_GS_ENCODER, "encoder", SH2000_PT_I32, "counts" },
	{ SH2000_GS_FERR, "ferr", SH2000_PT_F32, "counts" },
	{ SH2000_GS_DAC, "dac", SH2000_PT_I32, "DAC codes" },
	{ SH2000_GS_PID_P, "pid_p", SH2000_PT_F32, "DAC codes" },
	{ SH2000_GS_PID_I, "pid_i", SH2000_PT_F32, "DAC codes" },
	{ SH2000_GS_PID_D, "pid_d", SH2000_PT_F32, "DAC codes" },
	{ SH2000_GS_FF, "ff", SH2000_PT_F32, "DAC codes" },
	{ SH2000_GS_VELOCITY, "velocity", SH2000_PT_F32, "counts/s" },
	{ SH2000_GS_SETPOINT_VEL, "setpoint_vel", SH2000_PT_F32, "counts/s" },
};
_Static_assert(sizeof(gather_signals) / sizeof(gather_signals[0]) ==
	       SH2000_GATHER_SIGNALS, "one row per gather signal");

const struct sh2000_gather_signal_info *sh2000_gather_signal_lookup(unsigned int id)
{
	return id < SH2000_GATHER_SIGNALS ? &gather_signals[id] : NULL;
}

const struct sh2000_gather_signal_info *sh2000_gather_signal_by_name(const char *name)
{
	unsigned int i;

	for (i = 0; name && i < SH2000_GATHER_SIGNALS; i++)
		if (!strcmp(gather_signals[i].name, name))
			return &gather_signals[i];
	return NULL;
}

const char *sh2000_state_name(unsigned int state)
{
	static const char *const n[] = {
		"boot", "idle", "running", "stopping", "homing", "fault",
		"estop",
	};

	return state < sizeof(n) / sizeof(n[0]) ? n[state] : "unknown state";
}

const char *sh2000_reject_name(unsigned int reason)
{
	static const char *const n[] = {
		"none", "bad record checksum", "reserved bits set",
		"step exceeds max velocity", "point beyond soft limit",
		"axis not enabled", "card not ready to move",
		"record dropped (injected)",
	};

	return reason < sizeof(n) / sizeof(n[0]) ? n[reason] :
						   "unknown reason";
}

const char *sh2000_result_name(unsigned int result)
{
	static const char *const n[] = {
		"ok", "unknown command", "bad axis", "unknown parameter",
		"value out of range", "busy (moving)", "fault latched",
		"command checksum wrong", "axis not enabled",
	};

	return result < sizeof(n) / sizeof(n[0]) ? n[result] :
						   "unknown result";
}

const char *sh2000_fault_name(unsigned int bit)
{
	switch (bit) {
	case SH2000_FAULT_UNDERRUN: return "segment underrun";
	case SH2000_FAULT_HOST_TIMEOUT: return "host heartbeat timeout";
	case SH2000_FAULT_ESTOP: return "emergency stop";
	case SH2000_FAULT_REJECTED: return "segment rejected";
	case SH2000_FAULT_PROTOCOL: return "protocol violation";
	case SH2000_FAULT_AXIS: return "axis fault";
	default: return "unknown fault";
	}
}

const char *sh2000_axis_fault_name(unsigned int bit)
{
	switch (bit) {
	case SH2000_AXIS_FAULT_FERR: return "following error";
	case SH2000_AXIS_FAULT_SOFT_LIMIT: return "soft limit";
	case SH2000_AXIS_FAULT_HARD_LIMIT: return "hard limit switch";
	case SH2000_AXIS_FAULT_DAC_SAT: return "DAC saturated";
	case SH2000_AXIS_FAULT_COUNTER: return "encoder counter jump";
	case SH2000_AXIS_FAULT_HOME: return "homing failed";
	case SH2000_AXIS_FAULT_SKEW: return "gantry skew";
	default: return "unknown axis fault";
	}
}
