// SPDX-License-Identifier: MIT
/*
 * A whole card in virtual time. Card time only moves when the host does
 * something: each port access costs SH2000_PORT_CYCLE_NS, and
 * sh2000_cardsim_advance() is a host waiting. Servo cycles run as time
 * crosses multiples of the servo period, in order, before the call
 * returns, so a run is a pure function of the host's calls.
 *
 * An access takes effect at the start of its port cycle; the servo cycles
 * that fall inside the cycle run after it.
 */
#include <stdlib.h>

#include "card_internal.h"

struct sh2000_cardsim {
	uint16_t ram[SH2000_RAM_WORDS];
	struct sh2000_fw *fw;
	struct sh2000_fpga *fpga;	/* the board's host side */
	uint64_t now_ns;
	uint64_t next_cycle_ns;	/* when the next servo interrupt fires */
};

int sh2000_cardsim_create(struct sh2000_cardsim **out,
			  const struct sh2000_sim_config *cfg)
{
	struct sh2000_cardsim *c;
	int err;

	if (!out)
		return -22;
	c = calloc(1, sizeof(*c));
	if (!c)
		return -12;
	err = sh2000_fw_create(&c->fw, c->ram, cfg);
	if (err) {
		free(c);
		return err;
	}
	c->fpga = sh2000_board_host(c->fw->hw);
	c->next_cycle_ns = sh2000_fw_servo_period_ns(c->fw);
	*out = c;
	return 0;
}

void sh2000_cardsim_destroy(struct sh2000_cardsim *c)
{
	if (!c)
		return;
	sh2000_fw_destroy(c->fw);
	free(c);
}

void sh2000_cardsim_advance(struct sh2000_cardsim *c, uint64_t ns)
{
	c->now_ns += ns;
	/* each cycle says when the next comes, in host time: the card's
	 * period (which may have changed inside it) and its clock's error */
	while (c->next_cycle_ns <= c->now_ns)
		c->next_cycle_ns += sh2000_card_cycle(c->fw);
}

void sh2000_cardsim_out(struct sh2000_cardsim *c, unsigned int reg, uint16_t v)
{
	sh2000_fpga_out(c->fpga, reg, v);
	sh2000_cardsim_advance(c, SH2000_PORT_CYCLE_NS);
}

uint16_t sh2000_cardsim_in(struct sh2000_cardsim *c, unsigned int reg)
{
	uint16_t v = sh2000_fpga_in(c->fpga, reg);

	sh2000_cardsim_advance(c, SH2000_PORT_CYCLE_NS);
	return v;
}

uint64_t sh2000_cardsim_now_ns(const struct sh2000_cardsim *c)
{
	return c->now_ns;
}

struct sh2000_fw *sh2000_cardsim_fw(struct sh2000_cardsim *c)
{
	return c->fw;
}

void sh2000_cardsim_counters(const struct sh2000_cardsim *c, uint64_t out[4])
{
	unsigned int i;

	for (i = 0; i < 4; i++)
		out[i] = c->fpga->counters[i];
}

uint16_t *sh2000_cardsim_ram(struct sh2000_cardsim *c)
{
	return c->ram;
}
