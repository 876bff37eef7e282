/* SPDX-License-Identifier: MIT */
#include <stdlib.h>
#include <string.h>

#include "fakecard.h"

static struct fakecard *F(struct sh2000 *h)
{
	return (struct fakecard *)h;
}

static void logit(struct fakecard *f, enum fake_op op)
{
	if (f->nlog < FAKE_LOG_MAX) {
		f->log[f->nlog].op = (uint8_t)op;
		f->log[f->nlog].addr = (uint16_t)f->counter;
		f->nlog++;
	}
}

static void tick(struct fakecard *f, uint64_t ns)
{
	uint64_t from = f->now_ns > f->stalled_until ? f->now_ns : f->stalled_until;

	f->now_ns += ns;
	if (f->hb_running && f->now_ns > from)
		f->ram[SH2000_W_HEARTBEAT] += (uint16_t)(f->now_ns / 100000u -
							 from / 100000u);
	if (f->stall_pending == SH2000_W_CMD_SEQ + 1 && f->now_ns > f->stalled_until) {
		f->ram[SH2000_W_CMD_RESULT] = f->ack_result;
		f->ram[SH2000_W_CMD_ACK] = f->ram[SH2000_W_CMD_SEQ];
	} else if (f->stall_pending && f->now_ns > f->stalled_until) {
		f->ram[SH2000_W_ESTOP_ACK] = f->ram[SH2000_W_ESTOP_REQ];
		f->ram[SH2000_W_STATE] = SH2000_STATE_ESTOP;
	}
	if (f->now_ns > f->stalled_until)
		f->stall_pending = 0;
}

static void fake_out(struct sh2000 *h, unsigned int reg, uint16_t v)
{
	struct fakecard *f = F(h);

	tick(f, 1000);
	switch (reg) {
	case SH2000_REG_ADDR_CLEAR:
		f->counter = 0;
		logit(f, FAKE_CLEAR);
		break;
	case SH2000_REG_ADDR_INC:
		f->counter = (f->counter + 1) & SH2000_ADDR_MASK;
		logit(f, FAKE_INC);
		break;
	case SH2000_REG_DATA:
		logit(f, FAKE_WR);
		f->ram[f->counter] = v;
		if ((f->counter == SH2000_W_CMD_SEQ ||
		     f->counter == SH2000_W_ESTOP_REQ) && f->stall_ns) {
			f->stalled_until = f->now_ns + f->stall_ns;
			f->stall_pending = (int)f->counter + 1;
			break;
		}
		if (f->counter == SH2000_W_CMD_SEQ && f->late_ack_ns) {
			f->ack_pending = 1;
		} else if (f->counter == SH2000_W_CMD_SEQ && f->auto_ack) {
			f->ram[SH2000_W_CMD_RESULT] = f->ack_result;
			f->ram[SH2000_W_CMD_VALUE_LO] = (uint16_t)f->ack_value;
			f->ram[SH2000_W_CMD_VALUE_HI] = (uint16_t)(f->ack_value >> 16);
			f->ram[SH2000_W_CMD_ACK] = v;
		}
		if (f->counter == SH2000_W_ESTOP_REQ && f->auto_ack) {
			f->ram[SH2000_W_ESTOP_ACK] = v;
			f->ram[SH2000_W_STATE] = SH2000_STATE_ESTOP;
		}
		break;
	}
}

static uint16_t fake_in(struct sh2000 *h, unsigned int reg)
{
	struct fakecard *f = F(h);
	uint16_t v;

	tick(f, 1000);
	logit(f, FAKE_RD);
	(void)reg;
	v = f->ram[f->counter];
	if (f->counter == SH2000_W_CMD_ACK && f->ack_pending) {
		f->ack_pending = 0;
		tick(f, f->late_ack_ns);
		f->ram[SH2000_W_CMD_RESULT] = f->ack_result;
		f->ram[SH2000_W_CMD_ACK] = f->ram[SH2000_W_CMD_SEQ];
	}
	if (f->counter == SH2000_W_SNAP_SEQ_BEGIN && f->tear_polls) {
		f->tear_polls--;
		v = (uint16_t)(v + 1);	/* the card published meanwhile */
		if (f->tear_moving) {	/* ... and goes on: the next one */
			f->ram[SH2000_W_SNAP_SEQ_END] = v;
			f->ram[SH2000_W_SNAP_SEQ_BEGIN] = v;
		}
	}
	return v;
}

static uint64_t fake_now(struct sh2000 *h)
{
	return F(h)->now_ns;
}

static void fake_wait(struct sh2000 *h, uint64_t ns)
{
	tick(F(h), ns);
}

struct fakecard *fakecard_new(void)
{
	struct fakecard *f = calloc(1, sizeof(*f));
	unsigned int a;

	f->be.kind = SH2000_BACKEND_SIM;
	f->h.arb.fd = -1;	/* one process: no lock file */
	f->be.virtual_time = 1;
	f->be.port_out = fake_out;
	f->be.port_in = fake_in;
	f->be.now_ns = fake_now;
	f->be.wait_ns = fake_wait;
	f->be.counters = sh2000_bus_counters;
	f->h.be = &f->be;
	f->h.bus.pos = SH2000_SEEK_UNKNOWN;
	f->h.hb.limit_ns = SH2000_HEARTBEAT_LIMIT_NS;
	strcpy(f->h.device, "fake");
	for (a = 0; a < SH2000_AXES; a++)
		f->h.scale[a] = 1000.0;
	pthread_mutex_init(&f->h.lock, NULL);
	pthread_cond_init(&f->h.cmd_cond, NULL);
	f->counter = 777;	/* unknown to the host */
	return f;
}

void fakecard_free(struct fakecard *f)
{
	pthread_cond_destroy(&f->h.cmd_cond);
	pthread_mutex_destroy(&f->h.lock);
	free(f);
}

void fakecard_boot(struct fakecard *f)
{
	f->ram[SH2000_W_MAGIC] = SH2000_PROTO_MAGIC;
	f->ram[SH2000_W_VERSION] = SH2000_PROTO_VERSION;
	f->ram[SH2000_W_STATE] = SH2000_STATE_IDLE;
	f->ram[SH2000_W_SNAP_SEQ_END] = 5;
	f->ram[SH2000_W_SNAP_SEQ_BEGIN] = 5;
	f->auto_ack = 1;
	f->hb_running = 1;
}

void fakecard_clear_log(struct fakecard *f)
{
	f->nlog = 0;
}

void fakecard_counts(const struct fakecard *f, unsigned int c[4])
{
	unsigned int i;

	memset(c, 0, 4 * sizeof(c[0]));
	for (i = 0; i < f->nlog; i++)
		c[f->log[i].op]++;
}
