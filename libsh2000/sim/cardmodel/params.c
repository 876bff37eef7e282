// SPDX-License-Identifier: MIT
/*
 * Axis and global parameters on the card side: where each one is stored,
 * which may change while moving, and the card's rules beyond the shared
 * range check (soft-limit order, representable servo period).
 */
#include <string.h>

#include "cardmodel.h"

static double *axis_f(struct sh2000_fw_params *p, unsigned int id)
{
	switch (id) {
	case SH2000_P_SCALE: return &p->scale;
	case SH2000_P_KP: return &p->kp;
	case SH2000_P_TI: return &p->ti;
	case SH2000_P_TD: return &p->td;
	case SH2000_P_KVFF: return &p->kvff;
	case SH2000_P_KAFF: return &p->kaff;
	case SH2000_P_VMAX: return &p->vmax;
	case SH2000_P_AMAX: return &p->amax;
	case SH2000_P_HOME_VEL: return &p->home_vel;
	default: return NULL;
	}
}

static int32_t *axis_i(struct sh2000_fw_params *p, unsigned int id)
{
	switch (id) {
	case SH2000_P_DAC_RANGE: return &p->dac_range;
	case SH2000_P_DAC_LIMIT: return &p->dac_limit;
	case SH2000_P_FERR_LIMIT: return &p->ferr_limit;
	case SH2000_P_SOFT_MIN: return &p->soft_min;
	case SH2000_P_SOFT_MAX: return &p->soft_max;
	case SH2000_P_HOME_DEBOUNCE: return &p->home_debounce;
	case SH2000_P_HOME_OFFSET: return &p->home_offset;
	default: return NULL;
	}
}

static int32_t *global_i(struct sh2000_dsp *fw, unsigned int id)
{
	switch (id) {
	case SH2000_GP_COARSE_PERIOD_US: return &fw->coarse_us;
	case SH2000_GP_FINE_STEPS: return &fw->fine_steps;
	case SH2000_GP_HOST_TIMEOUT_MS: return &fw->host_timeout_ms;
	case SH2000_GP_STATUS_PERIOD: return &fw->status_period;
	case SH2000_GP_TIME_SCALE: return &fw->time_scale;
	case SH2000_GP_TIME_RAMP_MS: return &fw->time_ramp_ms;
	case SH2000_GP_GANTRY_PAIR: return &fw->gantry.pair;
	case SH2000_GP_GANTRY_SKEW_LIMIT: return &fw->gantry.skew_limit;
	case SH2000_GP_GANTRY_SQUARE: return &fw->gantry.square;
	default: return NULL;
	}
}

static double *global_f(struct sh2000_dsp *fw, unsigned int id)
{
	switch (id) {
	case SH2000_GP_GANTRY_KP: return &fw->gantry.kp;
	case SH2000_GP_GANTRY_TI: return &fw->gantry.ti;
	case SH2000_GP_GANTRY_TD: return &fw->gantry.td;
	default: return NULL;
	}
}

/* A global parameter's word and its value, whatever its type. */
static uint32_t global_bits(struct sh2000_dsp *fw, unsigned int id)
{
	double *f = global_f(fw, id);

	return f ? sh2000_f32_bits(*f) : (uint32_t)*global_i(fw, id);
}

static void global_store(struct sh2000_dsp *fw, unsigned int id, double v)
{
	double *f = global_f(fw, id);

	if (f)
		*f = v;
	else
		*global_i(fw, id) = (int32_t)v;
}

uint16_t sh2000_fw_get_param(struct sh2000_dsp *fw, unsigned int axis,
			    unsigned int id, uint32_t *out)
{
	const struct sh2000_param_info *pi = sh2000_param_lookup(id);

	if (!pi)
		return SH2000_RES_BAD_PARAM;
	if (id >= SH2000_GP_FIRST) {
		if (axis != SH2000_AXIS_GLOBAL)
			return SH2000_RES_BAD_AXIS;
		*out = global_bits(fw, id);
		return SH2000_RES_OK;
	}
	if (axis >= SH2000_AXES)
		return SH2000_RES_BAD_AXIS;
	if (pi->type == SH2000_PT_F32)
		*out = sh2000_f32_bits(*axis_f(&fw->ax[axis].prm, id));
	else
		*out = (uint32_t)*axis_i(&fw->ax[axis].prm, id);
	return SH2000_RES_OK;
}

uint16_t sh2000_fw_set_param(struct sh2000_dsp *fw, unsigned int axis,
			    unsigned int id, uint32_t bits)
{
	const struct sh2000_param_info *pi = sh2000_param_lookup(id);
	double v;

	if (!pi)
		return SH2000_RES_BAD_PARAM;
	if (id >= SH2000_GP_FIRST ? axis != SH2000_AXIS_GLOBAL :
				    axis >= SH2000_AXES)
		return SH2000_RES_BAD_AXIS;
	v = pi->type == SH2000_PT_F32 ? sh2000_f32_value(bits) :
					(double)(int32_t)bits;
	if (sh2000_param_in_range(pi, v))
		return SH2000_RES_BAD_VALUE;
	if (sh2000_fw_in_motion(fw) && !pi->live)
		return SH2000_RES_BUSY;
	if (id >= SH2000_GP_FIRST) {
		if (id == SH2000_GP_COARSE_PERIOD_US &&
		    !sh2000_timing_ok((long long)v, fw->fine_steps))
			return SH2000_RES_BAD_VALUE;
		if (id == SH2000_GP_FINE_STEPS &&
		    !sh2000_timing_ok(fw->coarse_us, (long long)v))
			return SH2000_RES_BAD_VALUE;
		if (id == SH2000_GP_GANTRY_PAIR)
			sh2000_gantry_paired(fw);	/* a new pair: no history */
		global_store(fw, id, v);
		return SH2000_RES_OK;
	}
	if (id == SH2000_P_SOFT_MIN && !(v < fw->ax[axis].prm.soft_max))
		return SH2000_RES_BAD_VALUE;
	if (id == SH2000_P_SOFT_MAX && !(v > fw->ax[axis].prm.soft_min))
		return SH2000_RES_BAD_VALUE;
	if (pi->type == SH2000_PT_F32)
		*axis_f(&fw->ax[axis].prm, id) = v;
	else
		*axis_i(&fw->ax[axis].prm, id) = (int32_t)v;
	if (id == SH2000_P_DAC_RANGE)	/* the DAC7744's range is hardware */
		sh2000_board_write(fw->hw, axis, SH2000_HWREG_DAC_RANGE,
				   (uint32_t)v);
	return SH2000_RES_OK;
}

void sh2000_fw_default_params(struct sh2000_dsp *fw)
{
	unsigned int a, id;

	for (a = 0; a < SH2000_AXES; a++)
		for (id = 0; id < SH2000_AXIS_PARAMS; id++) {
			const struct sh2000_param_info *pi =
				sh2000_param_lookup(id);

			if (pi->type == SH2000_PT_F32)
				*axis_f(&fw->ax[a].prm, id) =
					(double)(float)pi->def;
			else
				*axis_i(&fw->ax[a].prm, id) = (int32_t)pi->def;
		}
	for (id = SH2000_GP_FIRST; id < SH2000_GP_END; id++)
		global_store(fw, id, sh2000_param_lookup(id)->def);
	for (a = 0; a < SH2000_AXES; a++)
		sh2000_board_write(fw->hw, a, SH2000_HWREG_DAC_RANGE,
				   (uint32_t)fw->ax[a].prm.dac_range);
}
