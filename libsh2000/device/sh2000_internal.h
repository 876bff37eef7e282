/* SPDX-License-Identifier: MIT */
/* The handle and the backends, shared by the library's source files. */
#ifndef SH2000_INTERNAL_H
#define SH2000_INTERNAL_H

#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000_seek.h"

#include "arbiter_state.h"
#include "backend.h"
#include "command_state.h"
#include "first_fault_state.h"
#include "mailbox_state.h"
#include "nonblock_state.h"
#include "status_state.h"

/*
 * Who calls whom, top to bottom; a file calls only files below it:
 *
 *   public calls   open.c, status.c, command.c, params.c, timing.c,
 *                  segment.c, gather.c, comp*.c, index.c, nonblock.c,
 *                  first_fault.c
 *   sequencing     motion_claim.c: the motion lock, then the mailbox's
 *                  count sync; the mailbox's close, then the lock's drop
 *   modules        mailbox.c (the point mailbox), command.c's slot
 *   word access    bus.c: sh2000_rd/sh2000_wr -> the backend's read/write
 *                  ops, else the register-level bus over its ports
 *   backends       backend_dev.c, backend_io.c (its word ops run the bus
 *                  under the arbiter's bus lock), backend_shm.c,
 *                  backend_ports.c (backend_simload.c opens one)
 *   leaves         arbiter.c (the locks between processes: the lock file
 *                  only, never the card), errors.c, clock.c's time
 *
 * Each part's state is a member of struct sh2000 whose type its own header
 * declares (backend.h, arbiter_state.h, status_state.h, command_state.h,
 * nonblock_state.h, first_fault_state.h, mailbox_state.h); a backend's
 * own state is behind h->priv, known to its file alone.
 */
struct sh2000 {
	pthread_mutex_t lock;
	pthread_cond_t cmd_cond;	/* the command slot became free */
	char device[128];
	char err[256];			/* errors.c: the last error message */

	const struct sh2000_backend *be;
	void *priv;			/* the backend's (backend_*.c) */
	struct sh2000_bus bus;		/* bus.c: register-level backends */
	struct sh2000_arb arb;		/* arbiter.c */

	unsigned int card_version;
	/* host-owned words, as this handle last wrote them (status.c,
	 * segment.c, mailbox.c) */
	uint16_t estop_req;
	uint16_t host_hb;
	uint64_t host_hb_ns;		/* when host_hb was last written */
	uint16_t head;			/* records published, ring and mailbox */
	uint64_t segments;		/* records pushed (segment numbers) */

	/* the card's timing and scales as last read/set (params.c) */
	uint64_t servo_ns;		/* coarse period / fine steps */
	int32_t coarse_us, fine_steps;
	double scale[SH2000_AXES];	/* counts per mm */

	struct sh2000_cmdslot cmd;	/* command.c */
	struct sh2000_hbwatch hb;	/* status.c */
	struct sh2000_ctrext ext;	/* status.c */
	struct sh2000_nb nb;		/* nonblock.c */
	struct sh2000_ff_cache first;	/* first_fault.c */
	struct sh2000_mbox mbox;	/* mailbox.c */
};

/* errors.c */
int sh2000_fail(struct sh2000 *h, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
int sh2000_msg(char *msg, size_t len, int code, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
/* An axis in messages: the lower-case letter of card.h's names, as every
 * tool and hal_sh2000 name it ('x' for 0), '?' for no axis of the card. */
char sh2000_axis_letter(int axis);
/* 0 if the card speaks protocol minor `minor` or later; else -EOPNOTSUPP
 * with "the card speaks protocol M.m: <what> 1.<minor>" (what ends with
 * its verb: "data gathering needs"). */
int sh2000_need_minor(struct sh2000 *h, unsigned int minor, const char *what);

/* bus.c: register-level access with lazy increments */
int sh2000_bus_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf);
int sh2000_bus_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf);
int sh2000_bus_counters(struct sh2000 *h, struct sh2000_port_counters *c);

/* Word access through the backend; the caller holds h->lock. */
int sh2000_rd(struct sh2000 *h, unsigned int addr, unsigned int n,
	      uint16_t *buf);
int sh2000_wr(struct sh2000 *h, unsigned int addr, unsigned int n,
	      const uint16_t *buf);
static inline int sh2000_wr1(struct sh2000 *h, unsigned int addr, uint16_t v)
{
	return sh2000_wr(h, addr, 1, &v);
}

/* Let time pass holding the lock for virtual time, releasing it else. */
void sh2000_hold_wait(struct sh2000 *h, uint64_t ns);
uint64_t sh2000_now_locked(struct sh2000 *h);

/* status.c, with the lock held */
/* Heartbeat limit from the servo period (or the caller's choice). */
void sh2000_timing_changed(struct sh2000 *h);
/* Wait until the card publishes its next snapshot. */
int sh2000_fresh_snapshot(struct sh2000 *h, int timeout_ms);
/* Age of the card heartbeat; sets hb.unsure when an unchanged value may
 * have wrapped (the caller re-reads it before calling the card stopped). */
uint64_t sh2000_hb_note(struct sh2000 *h, uint16_t hb, uint64_t now);
int sh2000_poll_locked(struct sh2000 *h, struct sh2000_status *st);
/* HOST_HEARTBEAT + 1 (the word after the status: one increment after a
 * poll); *now is the time of it. */
int sh2000_host_beat(struct sh2000 *h, uint64_t *now);
/* A decoded status' verdict: -SH2000_EMAGIC (firmware gone),
 * -SH2000_EHEARTBEAT (stopped for the limit), else 0. */
int sh2000_status_alive(struct sh2000 *h, const uint16_t *w,
			const struct sh2000_status *st);
/* A snapshot torn with the card heartbeat (st->heartbeat, aged
 * st->heartbeat_age_ns) standing still for the limit: -SH2000_EHEARTBEAT
 * naming the publication the card stopped in. */
int sh2000_torn_dead(struct sh2000 *h, const struct sh2000_status *st,
		     const uint16_t *w);
/* Fill *st from words 0..SH2000_STATUS_WORDS-1 of a consistent read
 * (extends the counters). */
void sh2000_status_decode(struct sh2000 *h, const uint16_t *w,
			  struct sh2000_status *st);
/* first_fault.c: st->first_fault from the status words w[] a poll read
 * (and decoded into *st), reading the record when the cached one may be
 * stale; tries: reads of a record torn by a RESET before giving up (it
 * is then left unknown). 0 or a bus error. */
int sh2000_first_fault_update(struct sh2000 *h, const uint16_t *w,
			      struct sh2000_status *st, unsigned int tries);
int sh2000_status_error_locked(struct sh2000 *h,
			       const struct sh2000_status *st);

/* segment.c: write n records from HEAD and publish them (HOST_HEARTBEAT
 * and HEAD); the caller has checked the room and the claim. Returns n. */
int sh2000_ring_write_locked(struct sh2000 *h,
			     const int32_t (*pts)[SH2000_AXES], size_t n,
			     unsigned int flags);
/* mailbox.c (h->lock held) */
/* The card speaks protocol 1.3 or later. */
int sh2000_mbox_card(const struct sh2000 *h);
/* The record count from the card's words (open, a motion claimed). */
int sh2000_queue_sync_locked(struct sh2000 *h);
/* Ring records up to `last` were published (HEAD written). */
void sh2000_mbox_ring_written(struct sh2000 *h,
			      const int32_t last[SH2000_AXES]);
/* Post pt through the mailbox: 1 posted, 0 the mailbox cannot carry it
 * now (use the ring), < 0 an error. */
int sh2000_mbox_post_locked(struct sh2000 *h, const int32_t pt[SH2000_AXES],
			    unsigned int flags);
/* A poll saw the card in this state. */
void sh2000_mbox_status(struct sh2000 *h, unsigned int card_state);
/* HEAD put level with the count, for a later host that knows only the
 * ring: by the handle that posted last (it closes or lets the motion
 * go). */
int sh2000_mbox_close_locked(struct sh2000 *h);

/* Write OP..CHECK and then CMD_SEQ = the next sequence number (the
 * caller holds the command slot); h->cmd.seq becomes it. */
int sh2000_cmd_write(struct sh2000 *h, unsigned int op, unsigned int axis,
		     unsigned int param, int32_t arg);
/* Map a command result code to its error. */
int sh2000_cmd_result_error(unsigned int res);
const char *sh2000_cmd_op_name(unsigned int op);

/* params.c, with the lock held: the word the card gets for parameter id
 * of axis (SH2000_GLOBAL) set to v, or -SH2000_EPARAM with the message
 * sh2000_param_set() gives; a global parameter's word read or set (the
 * handle's copy of the timing kept). */
int sh2000_param_check(struct sh2000 *h, int axis, unsigned int id,
		       double v, int32_t *word);
int sh2000_global_get_locked(struct sh2000 *h, unsigned int id, int32_t *word);
int sh2000_global_set_locked(struct sh2000 *h, unsigned int id, int32_t word);
/* softlimits.c, with the lock held: polls the card and judges the window
 * lo..hi (counts, going with scale) against axis' position as
 * sh2000_soft_limits_check() does; 0, or -SH2000_EPARAM with its reason
 * after "axis x WHAT: " (or the poll's error). */
int sh2000_soft_limits_locked(struct sh2000 *h, int axis, const char *what,
			      int32_t lo, int32_t hi, double scale);

/* command.c, with the lock held (it may release it while waiting) */
int sh2000_command_locked(struct sh2000 *h, unsigned int op,
			  unsigned int axis, unsigned int param, int32_t arg,
			  int32_t *value, int timeout_ms);
/* The same in parts, for exchanges that read the RAM before the slot is
 * given up (data gathering's window) or belong together: take the slot
 * (what names the caller in a timeout message), any number of exchanges
 * (write, wait for the acknowledgement, result as an error; *value gets
 * CMD_VALUE whatever the result), drop it. */
int sh2000_cmd_slot_take(struct sh2000 *h, const char *what);
int sh2000_cmd_exchange(struct sh2000 *h, unsigned int op, unsigned int axis,
			unsigned int param, int32_t arg, int32_t *value,
			int timeout_ms);
void sh2000_cmd_slot_drop(struct sh2000 *h);

/* arbiter.c (h->lock held) */
int sh2000_arb_open(struct sh2000 *h, const char *id, char *msg, size_t len);
void sh2000_arb_close(struct sh2000 *h);
int sh2000_arb_take(struct sh2000 *h, unsigned int which, short type,
		    int timeout_ms);
void sh2000_arb_drop(struct sh2000 *h, unsigned int which);
int sh2000_arb_bus_take(struct sh2000 *h);
int sh2000_arb_cmd_take(struct sh2000 *h);
/* The command lock tried once: -EAGAIN if another program has it, else
 * as sh2000_arb_cmd_take(). */
int sh2000_arb_cmd_try(struct sh2000 *h);
/* The motion lock alone: 1 newly taken, 0 held already or no lock file
 * (the in-process card), < 0 an error. */
int sh2000_arb_claim_locked(struct sh2000 *h);
/* This handle holds the motion lock. */
int sh2000_arb_holds_motion(const struct sh2000 *h);
/* Give the motion lock up (its holder record cleared); none held: 0. */
void sh2000_arb_release_locked(struct sh2000 *h);
/* Around a command that changes the motion (enable, disable, home,
 * set_position, reset): -SH2000_EOWNED naming the holder if another
 * program controls the motion. */
int sh2000_arb_motion_begin(struct sh2000 *h, const char *what);
void sh2000_arb_motion_end(struct sh2000 *h);

/* motion_claim.c (h->lock held): the motion lock taken with the record
 * count synced from the card (what every first push does): 0 or < 0. */
int sh2000_motion_claim_locked(struct sh2000 *h);

/* backends */
int sh2000_dev_open(struct sh2000 *h, const char *path, char *msg,
		    size_t len);
int sh2000_io_open(struct sh2000 *h, const char *spec, char *msg,
		   size_t len);
/* backend_ports.c: take over *p (closed on failure too) */
int sh2000_ports_attach(struct sh2000 *h, const struct sh2000_ports *p,
			char *msg, size_t len);
/* backend_simload.c: `sim` from libsh2000-sim's provider */
int sh2000_simload_open(struct sh2000 *h, char *msg, size_t len);
int sh2000_shm_open(struct sh2000 *h, const char *name, char *msg,
		    size_t len);

uint64_t sh2000_mono_ns(void);
void sh2000_sleep_real(uint64_t ns);

/* Little helpers for 32-bit values in two words. */
static inline int32_t sh2000_w32(const uint16_t *w)
{
	return (int32_t)((uint32_t)w[0] | ((uint32_t)w[1] << 16));
}


#endif /* SH2000_INTERNAL_H */
