/* SPDX-License-Identifier: MIT */
/*
 * Opening and closing a card by device string (or by port functions): the
 * backend, the card's hello and the arbiter; the handle's accessors, the
 * port-cycle counters and raw access to the dual-port RAM. The handle's
 * clock is clock.c's.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sh2000_internal.h"

/* How long a booting card may take to show its magic. */
#define OPEN_MAGIC_WAIT_NS	50000000ull
#define OPEN_POLL_STEP_NS	100000ull

const char *sh2000_device(const struct sh2000 *h)
{
	return h->device;
}

enum sh2000_backend_kind sh2000_backend(const struct sh2000 *h)
{
	return h->be->kind;
}

unsigned int sh2000_card_version(const struct sh2000 *h)
{
	return h->card_version;
}

/* Magic, version, the host-owned words, a live heartbeat, the scales. */
static int card_hello(struct sh2000 *h, char *msg, size_t len)
{
	struct sh2000_status st;
	uint16_t w[2], cmd[2];
	uint64_t t0 = sh2000_now_locked(h);
	unsigned int a;
	int r;

	for (;;) {
		r = sh2000_rd(h, SH2000_W_MAGIC, 2, w);
		if (r < 0)
			return sh2000_msg(msg, len, r, "%s: reading magic: %s",
					  h->device, h->err);
		if (w[0] == SH2000_PROTO_MAGIC)
			break;
		if (sh2000_now_locked(h) - t0 > OPEN_MAGIC_WAIT_NS)
			return sh2000_msg(msg, len, -SH2000_EMAGIC,
					  "%s: no firmware: magic word (%u) reads 0x%04x, expected 0x%04x",
					  h->device, SH2000_W_MAGIC, w[0],
					  SH2000_PROTO_MAGIC);
		sh2000_hold_wait(h, OPEN_POLL_STEP_NS);
	}
	h->card_version = w[1];
	if (SH2000_PROTO_VERSION_MAJOR(w[1]) != SH2000_PROTO_MAJOR)
		return sh2000_msg(msg, len, -SH2000_EVERSION,
				  "%s: protocol version mismatch: library speaks %u.x, card reports %u.%u",
				  h->device, SH2000_PROTO_MAJOR,
				  SH2000_PROTO_VERSION_MAJOR(w[1]),
				  SH2000_PROTO_VERSION_MINOR(w[1]));

	/* Continue the host-owned counters where the last host left them. */
	r = sh2000_rd(h, SH2000_W_ESTOP_REQ, 1, &h->estop_req);
	if (!r)
		r = sh2000_rd(h, SH2000_W_HOST_HEARTBEAT, 2, w);
	if (!r)
		r = sh2000_rd(h, SH2000_W_CMD_SEQ, 1, &cmd[0]);
	if (!r)
		r = sh2000_rd(h, SH2000_W_CMD_ACK, 1, &cmd[1]);
	if (r < 0)
		return sh2000_msg(msg, len, r, "%s: %s", h->device, h->err);
	h->host_hb = w[0];
	h->cmd.seq = cmd[0];
	r = sh2000_queue_sync_locked(h);
	if (r < 0)
		return sh2000_msg(msg, len, r, "%s: %s", h->device, h->err);

	/* The card heartbeat must move: one change within the limit. */
	r = sh2000_poll_locked(h, &st);
	if (r == 0) {
		uint16_t first = st.heartbeat;

		while (r == 0 && st.heartbeat == first) {
			sh2000_hold_wait(h, OPEN_POLL_STEP_NS);
			r = sh2000_poll_locked(h, &st);
		}
	}
	if (r < 0)
		return sh2000_msg(msg, len, r, "%s", h->err);

	if (cmd[0] != cmd[1]) {
		/* a command of an earlier host is still open: let it finish */
		uint64_t t1 = sh2000_now_locked(h);

		while (sh2000_now_locked(h) - t1 <
		       SH2000_CMD_TIMEOUT_MS * 1000000ull) {
			if (sh2000_rd(h, SH2000_W_CMD_ACK, 1, &cmd[1]) < 0 ||
			    cmd[1] == cmd[0])
				break;
			sh2000_hold_wait(h, OPEN_POLL_STEP_NS);
		}
	}

	r = sh2000_command_locked(h, SH2000_CMD_GET_PARAM, SH2000_AXIS_GLOBAL,
				  SH2000_GP_COARSE_PERIOD_US, 0, &h->coarse_us,
				  SH2000_CMD_TIMEOUT_MS);
	if (!r)
		r = sh2000_command_locked(h, SH2000_CMD_GET_PARAM,
					  SH2000_AXIS_GLOBAL, SH2000_GP_FINE_STEPS,
					  0, &h->fine_steps,
					  SH2000_CMD_TIMEOUT_MS);
	if (r < 0)
		return sh2000_msg(msg, len, r, "%s", h->err);
	sh2000_timing_changed(h);
	for (a = 0; a < SH2000_AXES; a++) {
		int32_t v;
		double f;

		r = sh2000_command_locked(h, SH2000_CMD_GET_PARAM, a,
					  SH2000_P_SCALE, 0, &v,
					  SH2000_CMD_TIMEOUT_MS);
		if (r < 0)
			return sh2000_msg(msg, len, r, "%s", h->err);
		f = sh2000_f32_value((uint32_t)v);
		h->scale[a] = f > 0 ? f : 1.0;
	}
	return 0;
}

static struct sh2000 *handle_new(const char *device)
{
	struct sh2000 *h = calloc(1, sizeof(*h));

	if (!h)
		return NULL;
	pthread_mutex_init(&h->lock, NULL);
	pthread_cond_init(&h->cmd_cond, NULL);
	h->arb.fd = -1;
	h->bus.pos = SH2000_SEEK_UNKNOWN;
	h->hb.limit_ns = SH2000_HEARTBEAT_LIMIT_NS;
	snprintf(h->device, sizeof(h->device), "%s", device);
	return h;
}

static void handle_free(struct sh2000 *h)
{
	sh2000_arb_close(h);
	if (h->be && h->be->close)
		h->be->close(h);
	free(h->priv);
	pthread_cond_destroy(&h->cmd_cond);
	pthread_mutex_destroy(&h->lock);
	free(h);
}

static int finish_open(struct sh2000 *h, struct sh2000 **out, char *msg,
		       size_t len)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = card_hello(h, msg, len);
	pthread_mutex_unlock(&h->lock);
	if (r < 0) {
		handle_free(h);
		return r;
	}
	h->err[0] = 0;
	*out = h;
	return 0;
}

/* The lock file of a card other programs can reach: named by the
 * backend after what identifies the card, whatever path or string opened
 * it. */
static int open_arbiter(struct sh2000 *h, char *msg, size_t len)
{
	char id[96];

	if (!h->be->lock_id || !h->be->lock_id(h, id, sizeof(id)))
		return 0;	/* in-process card: this handle's alone */
	return sh2000_arb_open(h, id, msg, len);
}

int sh2000_open(struct sh2000 **out, const char *device, char *msg,
		size_t msglen)
{
	struct sh2000 *h;
	int r;

	if (!out)
		return -EINVAL;
	*out = NULL;
	if (!device || !*device)
		device = getenv(SH2000_DEVICE_ENV);
	if (!device || !*device)
		device = SH2000_DEFAULT_DEVICE;
	if (strlen(device) >= sizeof(h->device))
		return sh2000_msg(msg, msglen, -ENAMETOOLONG,
				  "device string too long");
	h = handle_new(device);
	if (!h)
		return sh2000_msg(msg, msglen, -ENOMEM, "%s: out of memory",
				  device);
	if (!strcmp(device, "sim"))
		r = sh2000_simload_open(h, msg, msglen);
	else if (!strncmp(device, "sim:", 4))
		r = sh2000_shm_open(h, device + 4, msg, msglen);
	else if (!strncmp(device, "io:", 3))
		r = sh2000_io_open(h, device + 3, msg, msglen);
	else if (device[0] == '/' || device[0] == '.')
		r = sh2000_dev_open(h, device, msg, msglen);
	else
		r = sh2000_msg(msg, msglen, -EINVAL,
			       "%s: unknown device string (use /dev/sh2000-N, io:0xNNN, sim or sim:NAME)",
			       device);
	if (r >= 0)
		r = open_arbiter(h, msg, msglen);
	if (r < 0) {
		handle_free(h);
		return r;
	}
	sh2000_timing_changed(h);
	return finish_open(h, out, msg, msglen);
}

int sh2000_open_ports(struct sh2000 **out, const struct sh2000_ports *ports,
		      const char *name, char *msg, size_t msglen)
{
	struct sh2000 *h;
	int r;

	if (!out) {
		if (ports && ports->close)
			ports->close(ports->ctx);
		return -EINVAL;
	}
	*out = NULL;
	if (!name || !*name)
		name = "ports";
	h = strlen(name) < sizeof(h->device) ? handle_new(name) : NULL;
	if (!h) {
		if (ports && ports->close)
			ports->close(ports->ctx);
		return sh2000_msg(msg, msglen, -ENOMEM,
				  "%s: out of memory or name too long", name);
	}
	r = sh2000_ports_attach(h, ports, msg, msglen);
	if (r < 0) {
		handle_free(h);
		return r;
	}
	sh2000_timing_changed(h);
	return finish_open(h, out, msg, msglen);
}

void sh2000_close(struct sh2000 *h)
{
	if (!h)
		return;
	pthread_mutex_lock(&h->lock);
	(void)sh2000_mbox_close_locked(h);
	pthread_mutex_unlock(&h->lock);
	handle_free(h);
}

int sh2000_port_counters(struct sh2000 *h, struct sh2000_port_counters *c)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = h->be->counters(h, c);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_ram_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_rd(h, addr, n, buf);
	if (r == -EINVAL)
		sh2000_fail(h, r, "words %u..%u are outside the RAM", addr,
			    addr + n - 1);
	pthread_mutex_unlock(&h->lock);
	return r;
}

int sh2000_ram_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf)
{
	int r;

	pthread_mutex_lock(&h->lock);
	r = sh2000_wr(h, addr, n, buf);
	if (r == -EINVAL)
		sh2000_fail(h, r, "words %u..%u are outside the RAM", addr,
			    addr + n - 1);
	pthread_mutex_unlock(&h->lock);
	return r;
}
