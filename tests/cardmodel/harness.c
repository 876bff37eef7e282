// SPDX-License-Identifier: MIT
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "sh2000/sh2000.h"

static void observe(void *ctx, const struct sh2000_probe *p)
{
	struct harness *h = ctx;

	if (h->trace_len < h->trace_cap)
		h->trace[h->trace_len++] = *p;
}

void h_init(struct harness *h, const struct sh2000_sim_config *cfg)
{
	memset(h, 0, sizeof(*h));
	h->host_alive = 1;
	if (sh2000_fw_create(&h->fw, h->ram, cfg))
		abort();
}

void h_fini(struct harness *h)
{
	sh2000_fw_destroy(h->fw);
	free(h->trace);
	h->trace = NULL;
}

void h_trace(struct harness *h, unsigned int cap)
{
	free(h->trace);
	h->trace = calloc(cap, sizeof(*h->trace));
	h->trace_cap = cap;
	h->trace_len = 0;
	sh2000_fw_set_observer(h->fw, observe, h);
}

uint16_t h_word(struct harness *h, unsigned int w)
{
	return sh2000_dpram_read(h->ram, w);
}

static void hw(struct harness *h, unsigned int w, uint16_t v)
{
	sh2000_dpram_write(h->ram, w, v);
}

void h_cycles(struct harness *h, unsigned int n)
{
	while (n--) {
		if (h->host_alive)
			hw(h, SH2000_W_HOST_HEARTBEAT,
			   (uint16_t)(h_word(h, SH2000_W_HOST_HEARTBEAT) + 1));
		sh2000_fw_cycle(h->fw);
	}
}

void h_cmd_post(struct harness *h, uint16_t op, uint16_t axis,
		uint16_t param, uint32_t arg)
{
	uint16_t lo = (uint16_t)arg, hi = (uint16_t)(arg >> 16);

	h->seq++;
	hw(h, SH2000_W_CMD_OP, op);
	hw(h, SH2000_W_CMD_AXIS, axis);
	hw(h, SH2000_W_CMD_PARAM, param);
	hw(h, SH2000_W_CMD_ARG_LO, lo);
	hw(h, SH2000_W_CMD_ARG_HI, hi);
	hw(h, SH2000_W_CMD_CHECK,
	   sh2000_cmd_check(h->seq, op, axis, param, lo, hi));
	hw(h, SH2000_W_CMD_SEQ, h->seq);
}

uint16_t h_cmd(struct harness *h, uint16_t op, uint16_t axis, uint16_t param,
	       uint32_t arg, uint32_t *value)
{
	unsigned int i;

	h_cmd_post(h, op, axis, param, arg);
	for (i = 0; i < 10 && h_word(h, SH2000_W_CMD_ACK) != h->seq; i++)
		h_cycles(h, 1);
	if (h_word(h, SH2000_W_CMD_ACK) != h->seq)
		return 0xffff;
	if (value)
		*value = h_word(h, SH2000_W_CMD_VALUE_LO) |
			 ((uint32_t)h_word(h, SH2000_W_CMD_VALUE_HI) << 16);
	return h_word(h, SH2000_W_CMD_RESULT);
}

uint16_t h_set_f(struct harness *h, unsigned int axis, unsigned int id,
		 double v)
{
	float f = (float)v;
	uint32_t b;

	memcpy(&b, &f, sizeof(b));
	return h_cmd(h, SH2000_CMD_SET_PARAM, (uint16_t)axis, (uint16_t)id, b,
		     NULL);
}

uint16_t h_set_i(struct harness *h, unsigned int axis, unsigned int id,
		 int32_t v)
{
	return h_cmd(h, SH2000_CMD_SET_PARAM, (uint16_t)axis, (uint16_t)id,
		     (uint32_t)v, NULL);
}

unsigned int h_fill(struct harness *h)
{
	return (uint16_t)(h->head - h_word(h, SH2000_W_TAIL));
}

int h_push(struct harness *h, const int32_t pos[SH2000_AXES], uint16_t seq,
	   uint16_t flags)
{
	uint16_t rec[SH2000_RECORD_WORDS] = { 0 };
	unsigned int a, i, base;

	if (h_fill(h) >= SH2000_RING_RECORDS)
		return -1;
	for (a = 0; a < SH2000_AXES; a++) {
		rec[SH2000_REC_POS_LO(a)] = (uint16_t)(uint32_t)pos[a];
		rec[SH2000_REC_POS_HI(a)] = (uint16_t)((uint32_t)pos[a] >> 16);
	}
	rec[SH2000_REC_SEQ] = seq;
	rec[SH2000_REC_FLAGS] = flags;
	rec[SH2000_REC_CHECK] = sh2000_record_check(rec);
	base = SH2000_W_RING_BASE +
	       (h->head % SH2000_RING_RECORDS) * SH2000_RECORD_WORDS;
	for (i = 0; i < SH2000_RECORD_WORDS; i++)
		hw(h, base + i, rec[i]);
	h->head++;
	hw(h, SH2000_W_HEAD, h->head);
	return 0;
}

unsigned int h_stream(struct harness *h, const int32_t (*pts)[SH2000_AXES],
		      unsigned int n, unsigned int limit)
{
	unsigned int next = 0, cycles = 0;

	while (cycles < limit) {
		while (next < n &&
		       !h_push(h, pts[next], (uint16_t)next,
			       next + 1 == n ? SH2000_REC_F_END : 0))
			next++;
		h_cycles(h, 1);
		cycles++;
		if (next == n && h_word(h, SH2000_W_STATE) != SH2000_STATE_RUNNING)
			break;
	}
	return cycles;
}

int h_post(struct harness *h, const int32_t pos[SH2000_AXES])
{
	uint16_t m[SH2000_MBOX_WORDS];
	unsigned int i;

	if (h_word(h, SH2000_W_POSTED) != h->head ||
	    h_fill(h) >= SH2000_RING_RECORDS ||
	    h_word(h, SH2000_W_MBOX + SH2000_MBOX_SEQ) == h->head)
		return -1;
	sh2000_mbox_pack(m, pos, h->head);
	for (i = 0; i < SH2000_MBOX_WORDS; i++)
		hw(h, SH2000_W_MBOX + i, m[i]);	/* SEQ last */
	h->head++;
	return 0;
}

void h_snapshot(struct harness *h, int32_t cmd[SH2000_AXES],
		uint32_t act[SH2000_AXES])
{
	uint16_t end, begin;
	unsigned int a;

	do {
		end = h_word(h, SH2000_W_SNAP_SEQ_END);
		for (a = 0; a < SH2000_AXES; a++) {
			unsigned int w = SH2000_W_SNAP_AXIS(a);

			cmd[a] = (int32_t)(h_word(h, w + SH2000_SNAP_CMD_LO) |
					   ((uint32_t)h_word(h, w + SH2000_SNAP_CMD_HI)
					    << 16));
			act[a] = h_word(h, w + SH2000_SNAP_ACT_LO) |
				 ((uint32_t)h_word(h, w + SH2000_SNAP_ACT_HI) << 16);
		}
		begin = h_word(h, SH2000_W_SNAP_SEQ_BEGIN);
	} while (begin != end);
}

unsigned int h_trapezoid(double from, double to, double v, double a,
			 double coarse_s, double *out, unsigned int cap)
{
	double d = fabs(to - from), s = to > from ? 1.0 : -1.0;
	double ta = v / a, da = 0.5 * a * ta * ta, tc, total, t;
	unsigned int n = 0;

	if (2.0 * da > d) {
		ta = sqrt(d / a);
		da = d / 2.0;
		v = a * ta;
	}
	tc = (d - 2.0 * da) / v;
	total = 2.0 * ta + tc;
	for (t = coarse_s; n < cap; t += coarse_s) {
		double x;

		if (t >= total) {
			out[n++] = to;
			break;
		}
		if (t < ta)
			x = 0.5 * a * t * t;
		else if (t < ta + tc)
			x = da + v * (t - ta);
		else
			x = d - 0.5 * a * (total - t) * (total - t);
		out[n++] = from + s * x;
	}
	return n;
}

static struct harness fixture;

/* The image's pages through the RAM window, then the switch: the first
 * command's result that was not OK (with its op), or OK. */
static uint16_t comp_send(struct harness *h, const uint16_t *w, size_t n,
			  uint16_t *op)
{
	size_t first, k, i;
	uint16_t r;

	*op = SH2000_CMD_COMP_BEGIN;
	r = h_cmd(h, *op, 0, 0, (uint32_t)n, NULL);
	for (first = 0; r == SH2000_RES_OK && first < n; first += k) {
		k = n - first < SH2000_COMP_PAGE_WORDS ? n - first : SH2000_COMP_PAGE_WORDS;
		for (i = 0; i < k; i++)
			sh2000_dpram_write(h->ram, SH2000_W_COMP_PAGE + 1u + (unsigned int)i,
					   w[first + i]);
		sh2000_dpram_write(h->ram, SH2000_W_COMP_PAGE,
				   sh2000_comp_page_check((uint32_t)first, &w[first],
							  (unsigned int)k));
		*op = SH2000_CMD_COMP_PAGE;
		r = h_cmd(h, *op, 0, (uint16_t)k, (uint32_t)first, NULL);
	}
	if (r != SH2000_RES_OK)
		return r;
	*op = SH2000_CMD_COMP_COMMIT;
	return h_cmd(h, *op, 0, 0, sh2000_comp_sum(w, n), NULL);
}

int h_comp_load(struct harness *h, const char *text, char *msg,
		unsigned int len)
{
	static const double scale[SH2000_AXES] = { 1e5, 1e5, 1e5, 1e5 };
	char path[] = "/tmp/h_comp_XXXXXX";
	struct sh2000_comp_file *f = NULL;
	const uint16_t *w;
	size_t n;
	FILE *out;
	uint16_t res, op;
	int fd = mkstemp(path), r;

	if (fd < 0 || !(out = fdopen(fd, "w"))) {
		snprintf(msg, len, "comp: no temporary file");
		return -1;
	}
	fputs(text, out);
	r = fclose(out) ? -1 : sh2000_comp_file_read(&f, path, scale, msg, len);
	unlink(path);
	if (r)
		return -1;
	w = sh2000_comp_file_image(f, &n);
	res = comp_send(h, w, n, &op);
	sh2000_comp_file_free(f);
	if (res == SH2000_RES_OK)
		return 0;
	snprintf(msg, len, "comp: command %u answered %u (value 0x%04x%04x)", op,
		 res, h_word(h, SH2000_W_CMD_VALUE_HI), h_word(h, SH2000_W_CMD_VALUE_LO));
	return -1;
}

int h_setup(void **state)
{
	h_init(&fixture, NULL);
	*state = &fixture;
	return 0;
}

int h_setup_enabled(void **state)
{
	h_setup(state);
	/* cmocka's assertions need its headers; a plain check is enough */
	if (h_cmd(&fixture, SH2000_CMD_ENABLE, 0, 0, 0x3, NULL) != SH2000_RES_OK) {
		h_fini(&fixture);
		return -1;
	}
	return 0;
}

int h_teardown(void **state)
{
	h_fini(*state);
	return 0;
}
