/* SPDX-License-Identifier: MIT */
/*
 * Drives the card firmware through its RAM the way a host would, without
 * the library: commands with correct check words, records into the ring,
 * servo cycles run one by one. Each servo cycle the harness also bumps the
 * host heartbeat unless told not to.
 */
#ifndef SH2000_TEST_HARNESS_H
#define SH2000_TEST_HARNESS_H

#include <stdint.h>

#include "card_internal.h"

struct harness {
	uint16_t ram[SH2000_RAM_WORDS];
	struct sh2000_fw *fw;
	uint16_t seq, head;
	int host_alive;
	/* trace of the last run, filled by the observer */
	struct sh2000_probe *trace;
	unsigned int trace_len, trace_cap;
};

void h_init(struct harness *h, const struct sh2000_sim_config *cfg);
void h_fini(struct harness *h);
void h_cycles(struct harness *h, unsigned int n);
uint16_t h_word(struct harness *h, unsigned int w);
/* Publishes a command; runs cycles until it is acknowledged. */
uint16_t h_cmd(struct harness *h, uint16_t op, uint16_t axis, uint16_t param,
	       uint32_t arg, uint32_t *value);
/* Publishes a command without waiting. */
void h_cmd_post(struct harness *h, uint16_t op, uint16_t axis,
		uint16_t param, uint32_t arg);
uint16_t h_set_f(struct harness *h, unsigned int axis, unsigned int id,
		 double v);
uint16_t h_set_i(struct harness *h, unsigned int axis, unsigned int id,
		 int32_t v);
/* Writes record HEAD (positions, seq, flags, correct check); HEAD += 1.
 * Returns -1 when the ring is full. */
int h_push(struct harness *h, const int32_t pos[SH2000_AXES], uint16_t seq,
	   uint16_t flags);
unsigned int h_fill(struct harness *h);
/* Posts pos as record HEAD through the mailbox (protocol 1.3), SEQ
 * written last; the count h->head += 1, the HEAD word stays. Returns -1
 * unless the card has received everything (POSTED = h->head) and has
 * room. */
int h_post(struct harness *h, const int32_t pos[SH2000_AXES]);
/* Streams pts[0..n-1] (all axes), last with END, keeping the ring
 * topped up and running cycles until the card is idle again or `limit`
 * cycles passed. Returns the cycles run. */
unsigned int h_stream(struct harness *h, const int32_t (*pts)[SH2000_AXES],
		      unsigned int n, unsigned int limit);
/* Start recording probes into h->trace (cap entries). */
void h_trace(struct harness *h, unsigned int cap);
/* 32-bit snapshot values, read with the torn-read rule. */
void h_snapshot(struct harness *h, int32_t cmd[SH2000_AXES],
		uint32_t act[SH2000_AXES]);
/* A trapezoidal 1-D move sampled every coarse period. Returns points. */
unsigned int h_trapezoid(double from, double to, double v, double a,
			 double coarse_s, double *out, unsigned int cap);

/*
 * Compensation tables (docs/compensation.md's file text, every axis at
 * 1e5 counts/mm) read by the library's file reader and paged in, then
 * committed, as the library would send them: one owner of the file's
 * format. Does not wait for the blend. 0, or -1 with the reason in msg.
 */
int h_comp_load(struct harness *h, const char *text, char *msg,
		unsigned int len);

/*
 * cmocka fixtures: a fresh card with axes 0 and 1 enabled (h_setup_enabled)
 * or just booted (h_setup); h_teardown frees it. *state is the harness.
 */
int h_setup(void **state);
int h_setup_enabled(void **state);
int h_teardown(void **state);

#endif
