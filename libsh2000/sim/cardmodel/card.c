// SPDX-License-Identifier: MIT
/*
 * A card on a RAM: one board, the firmware on its DSP, and the servo
 * interrupt between them. A servo cycle is the firmware's interrupt
 * followed by the board running until the next one with the DAC outputs
 * held; a stalled DSP takes no interrupt, the board runs all the same.
 */
#include <stdlib.h>

#include "card_internal.h"

int sh2000_fw_create(struct sh2000_fw **out, uint16_t *ram,
		     const struct sh2000_sim_config *cfg)
{
	struct sh2000_sim_config def;
	struct sh2000_fw *fw;
	int err;

	if (!out || !ram)
		return -22;	/* -EINVAL */
	if (!cfg) {
		sh2000_sim_config_default(&def);
		cfg = &def;
	}
	fw = calloc(1, sizeof(*fw));
	if (!fw)
		return -12;	/* -ENOMEM */
	err = sh2000_board_create(&fw->hw, ram, cfg);
	if (err) {
		free(fw);
		return err;
	}
	sh2000_dsp_boot(&fw->dsp, fw->hw);
	*out = fw;
	return 0;
}

void sh2000_fw_destroy(struct sh2000_fw *fw)
{
	if (!fw)
		return;
	sh2000_board_destroy(fw->hw);
	free(fw);
}

uint64_t sh2000_fw_servo_period_ns(const struct sh2000_fw *fw)
{
	return sh2000_dsp_servo_period_ns(&fw->dsp);
}

uint64_t sh2000_card_cycle(struct sh2000_fw *fw)
{
	uint64_t card_ns, host_ns;

	if (fw->stall_left) {
		if (fw->stall_left != SH2000_STALL_FOREVER)
			fw->stall_left--;
	} else {
		sh2000_dsp_interrupt(&fw->dsp);
	}
	/* the timer is reprogrammed inside the interrupt when the period
	 * changes: the next one comes after the new period */
	card_ns = sh2000_dsp_servo_period_ns(&fw->dsp);
	host_ns = sh2000_board_run(fw->hw, card_ns);
	fw->time_ns += card_ns;
	if (fw->observer) {
		struct sh2000_probe p;

		sh2000_fw_probe(fw, &p);
		fw->observer(fw->observer_ctx, &p);
	}
	return host_ns;
}

void sh2000_fw_cycle(struct sh2000_fw *fw)
{
	(void)sh2000_card_cycle(fw);
}

void sh2000_fw_probe(const struct sh2000_fw *fw, struct sh2000_probe *p)
{
	unsigned int a;

	p->servo_cycle = fw->dsp.cycle;
	p->time_ns = fw->time_ns;
	p->state = fw->dsp.state;
	for (a = 0; a < SH2000_AXES; a++) {
		const struct sh2000_fw_axis *ax = &fw->dsp.ax[a];

		p->axis[a].fine_cmd = ax->cmd;
		p->axis[a].actual = (double)ax->act;
		p->axis[a].velocity =
			sh2000_plant_velocity(sh2000_board_plant(fw->hw, a));
		p->axis[a].dac = ax->dac;
	}
}

void sh2000_fw_tool_position(const struct sh2000_fw *fw,
			     double tool_mm[SH2000_AXES])
{
	sh2000_board_tool(fw->hw, tool_mm);
}

int sh2000_fw_set_geometry(struct sh2000_fw *fw, const struct sh2000_geometry *g)
{
	return fw ? sh2000_board_set_geometry(fw->hw, g) : -22;
}

void sh2000_fw_comp_offset(const struct sh2000_fw *fw,
			   double off[SH2000_AXES])
{
	unsigned int a;

	for (a = 0; a < SH2000_AXES; a++)
		off[a] = fw->dsp.comp.off[a];
}

void sh2000_fw_set_observer(struct sh2000_fw *fw, sh2000_fw_observer fn,
			    void *ctx)
{
	fw->observer = fn;
	fw->observer_ctx = ctx;
}

int sh2000_fw_set_clock_ppm(struct sh2000_fw *fw, double ppm)
{
	if (!fw)
		return -22;
	return sh2000_board_set_clock_ppm(fw->hw, ppm);
}

double sh2000_fw_clock_ppm(const struct sh2000_fw *fw)
{
	return sh2000_board_clock_ppm(fw->hw);
}

int sh2000_fw_set_gantry(struct sh2000_fw *fw,
			 const struct sh2000_gantry_config *g)
{
	if (!fw)
		return -22;
	return sh2000_board_set_gantry(fw->hw, g);
}

double sh2000_fw_gantry_yaw_mm(const struct sh2000_fw *fw)
{
	return sh2000_board_gantry_yaw_mm(fw->hw);
}
