/* SPDX-License-Identifier: GPL-2.0-or-later */
/*
 * hal_sh2000's logic without LinuxCNC ("hsc": HAL sh2000 card): one card
 * driven by a periodic servo thread through libsh2000's real-time calls
 * only (sh2000_poll_once, sh2000_command_start/complete, sh2000_push_point,
 * sh2000_estop_request). hal_sh2000.c copies HAL pins in and out of the
 * plain structs below; the tests drive the same code against the card
 * model without LinuxCNC. docs/linuxcnc.md explains the behaviour.
 */
#ifndef HSC_H
#define HSC_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

#include "sh2000/sh2000.h"

/* Records queued ahead of the card by default: 4 ms at a 1 ms period, so
 * a servo thread late by up to 3 ms does not starve the card. */
#define HSC_QUEUE_TARGET	4
/* How far the fill may stray from the target before the stream stalls
 * or drops a point (the clock correction normally keeps it within 1). */
#define HSC_FILL_SLACK		8
/* A record may be pushed this much of a tick before the command it holds
 * (extrapolated from the last two ticks): half a tick centres the queue
 * on the target. */
#define HSC_LEAD		0.5
/* Records pushed in one tick by the stream (a further card whose clock is
 * faster than the thread needs two now and then, and records owed after a
 * stall go out two a tick). */
#define HSC_MAX_PUSH		2
/* Ticks the fill must stay beyond its slack, ahead of the schedule,
 * before the card is taken to have slipped and the stream is re-centred.
 * Shorter, a stall of the whole machine that the card then catches up (a
 * served card catches up a stall of up to 50 ms in as long again, after
 * the thread has run its missed ticks back to back: some 100 ticks) looks
 * like a slip while it lasts, and every record dropped for it would move
 * the card's timeline for good: one servo period of skew against the
 * other cards and a jump of a period's motion in the set-point. */
#define HSC_SLIP_TICKS		250
/* How much faster than the thread's time the records sample the command
 * while the stream catches up a card that slipped: the card plays the
 * motion 5 % faster until the fill is back at the target (a slip of 40
 * periods takes 800 ticks), rather than jump over what it missed (a
 * step of 40 periods' motion, which the card refuses). */
#define HSC_SLIP_RATE		0.05
/* The fill's natural centre is target - 1 records (this tick's record is
 * pushed half a tick ahead of a card that takes one a period). When the
 * median over HSC_SLIP_TICKS fresh readings sits this far below it, the
 * stream lost records it will not get back (the card played them while
 * the thread was away and nothing owes them), and the queue guards the
 * card against the thread's lateness by that much less: the stream is
 * re-centred upwards at HSC_SLIP_RATE. The first card's fill sits on its
 * centre (the thread follows its clock); a further card's moves within a
 * record with the phase of its clock against the thread's, so its
 * allowance is a record wider. */
#define HSC_LOW_SLACK		2
/* Delay measurements (feedback.c) after which a stream's start is
 * checked against its phase reference (write.c). */
#define HSC_START_READINGS	100
/* How often a thread beside the servo thread reads the card's tables
 * again (sh2000.N.comp-*), so that a load or clear by another program
 * (sh2000ctl comp) shows within this; ms. */
#define HSC_COMP_WATCH_MS	500
/* Readings of the fill kept per window (a fill beyond counts as the last
 * bin: only a low median is judged). */
#define HSC_FILL_BINS		128
/* Ticks of the pins' commands kept, for records pushed late (owed while
 * the ring was full): they hold the command of their own time. */
#define HSC_CMD_HISTORY		128u
/* Servo cycles per coarse period the driver aims at (100 us at 1 ms). */
#define HSC_SERVO_NS		100000

struct hsc_axis_in {
	double position_cmd;	/* machine units */
	int enable;
	int index_enable;
	/* hostmot2's encoder parameters of the same names (index.c) */
	int index_mask, index_mask_invert, index_invert;
	/* index-within: the travel (machine units) an arm allows for the
	 * mark, 0: no limit (the driver's own; index.c) */
	double index_within;
	double position_scale;	/* counts per machine unit */
};

struct hsc_axis_out {
	double position_fb;	/* aligned with the command's delay */
	double encoder_position;	/* raw encoder, machine units */
	double f_error;		/* the card's own, machine units */
	int32_t counts;
	int amp_fault;
	int home_sw, limit_pos, limit_neg;
	int index_enable;
};

struct hsc_in {
	int estop;
	int fault_reset;
	int queue_target;	/* records; <= 0: HSC_QUEUE_TARGET */
	struct hsc_axis_in axis[SH2000_AXES];
};

struct hsc_out {
	int ok;
	int fault;
	int32_t queue_fill;
	int32_t card_state;
	uint32_t underruns;
	uint32_t port_cycles;	/* of the last read + write */
	int32_t pll_correction_ns;
	double delay_ms;	/* command to the card's set-point, 0 unknown */
	struct hsc_axis_out axis[SH2000_AXES];
};

/* Why the driver stopped streaming on its own (latched until
 * fault-reset). */
enum hsc_stream_fault {
	HSC_SF_NONE = 0,
	HSC_SF_LOST,		/* card heartbeat or firmware gone */
	HSC_SF_STOPPED,		/* another program stopped the motion */
	HSC_SF_POINT,		/* a command not representable in counts */
	HSC_SF_CONFIG,		/* the card refused the timing */
	HSC_SF_COMMAND,		/* a command failed */
};

/* The clock of the card against the servo thread's (timebase.c). */
struct hsc_timebase {
	int follow;		/* a virtual clock follows the card, not
				 * the thread (cards after the first) */
	int locked;		/* has a reference */
	uint64_t hb_ext;	/* heartbeat extended to 64 bits */
	uint16_t hb_last;
	uint64_t hb0;		/* heartbeat at the reference */
	uint64_t tick0;		/* tick at the reference */
	double off;		/* lateness of the reference read, records */
	double integ;		/* PI integrator, records per tick */
	double phase;		/* last phase error, records */
	double centre;		/* the phase errors taken, averaged over
				 * some TB_CENTRE_N readings: what the
				 * next one is judged against */
	int readings;		/* since the reference (up to
				 * TB_REF_READINGS) */
	int ahead_n;		/* ...of those, ahead in a row */
	double ahead_min;	/* the least of them */
	int outliers;		/* readings skipped in a row */
	int outlier_side;	/* +1 ahead, -1 behind */
	int settled;		/* ...of which the last agree */
	double skipped;		/* the last skipped phase, records */
	double rate;		/* card records per tick - 1 (estimate) */
	double correction;	/* clock period correction, fraction */
	double clock;		/* the clock the card is compared with,
				 * records since the reference: the
				 * thread's ticks, or the virtual clock */
	double step;		/* how far it moved this tick, records */
	uint64_t tick_last;	/* tick of the last advance */
};

/* index-enable of one axis (index.c). */
enum hsc_index_phase {
	HSC_IX_IDLE = 0,	/* nothing armed by the driver */
	HSC_IX_ARMING,		/* INDEX_ARM in flight */
	HSC_IX_ARMED,		/* the card waits for a mark */
};

struct hsc_index {
	enum hsc_index_phase phase;
	unsigned int arm;	/* the card's number of our arm */
	int want_last;		/* index-enable was already taken */
	int fault;		/* could not be honoured: amp-fault */
	int latched;		/* the mark came in this tick's read */
	int have_offset;	/* a mark has been latched since load */
	int64_t offset;		/* counts at that mark: position-fb's zero */
};

#define HSC_HISTORY	256u	/* records of commands kept (power of 2) */

/*
 * comp.c's watch of the card's tables. sh2000_comp_status() is not a
 * real-time call (it waits for the handle's and the card's locks), so a
 * thread of its own reads it every period_ms through a handle of its own
 * (as another program would: it never holds the servo thread's handle)
 * and leaves it in `seen`; the servo thread only tries the lock and takes
 * it when fresh.
 */
struct hsc_comp_watch {
	pthread_t thread;
	struct sh2000 *h;	/* the watch's handle; NULL: the card's (the
				 * in-process sim, which has one handle) */
	pthread_mutex_t lock;	/* the fields below */
	pthread_cond_t wake;	/* stop */
	int started;		/* set before the servo thread runs */
	int stop;
	unsigned int period_ms;
	struct sh2000_comp_status seen;	/* the last read */
	int fresh;		/* seen not taken yet */
	uint32_t reads;		/* reads done (tests wait on it) */
};

struct hsc_card {
	struct sh2000 *h;
	char device[128];
	int index;		/* N of sh2000.N */
	int master;		/* slaves the servo thread (the first card) */
	int io_thread_ready;	/* io: ioperm() done in the servo thread */

	/* what the card last showed */
	struct sh2000_status st;
	int st_valid;		/* a consistent status was read */
	int st_fresh;		/* ...in this tick's read */
	int lost;		/* heartbeat/magic: the card is gone */
	unsigned int last_faults;

	/* the timing the driver set on the card */
	long period_ns;		/* servo thread period, 0 before the first tick */
	int configured;		/* coarse period etc. set for period_ns */
	int cfg_step;
	/* the sets that take the card's timing to the thread's */
	struct sh2000_timing_step tsteps[SH2000_TIMING_STEPS_MAX];
	int ntsteps;

	/* one command in flight at a time */
	int cmd_busy;
	unsigned int cmd_op;
	unsigned int cmd_arg;

	/* enabling and streaming */
	unsigned int want_mask;	/* enable pins */
	int streaming;
	int stream_ticks;
	int seen_running;	/* the card has run this stream */
	int ending;		/* END pushed, waiting for idle */
	enum hsc_stream_fault sfault;
	int reset_edge, reset_last;
	int estop_last;
	uint64_t estop_tick;
	uint64_t tick;

	/*
	 * The stream's records as commanded (counts, every axis) and the
	 * thread time (ticks) of the command each one holds: rec[k %
	 * HSC_HISTORY] is the stream's k-th record. The card plays them one
	 * per coarse period of its clock, so feedback.c matches its
	 * set-points against them in the card's time.
	 */
	int32_t rec[HSC_HISTORY][SH2000_AXES];
	double rec_t[HSC_HISTORY];
	uint64_t rec_n;		/* records of this stream the card has */
	double due;		/* the stream's schedule: records due after
				 * the first batch, on the card's clock */
	long servo_ns;		/* the card's servo period as configured */
	long late_ns;		/* this tick's lateness */
	int queue_target;	/* records, as the pin last said */
	double snap_t;		/* card time of the snapshot, periods */
	int delay_valid;
	double delay;		/* command to card set-point, card time */
	int clock_off_valid;
	double clock_off;	/* PC time - card time of snapshots */
	int32_t last_cmd[SH2000_AXES];	/* this tick's command */
	int32_t prev_cmd[SH2000_AXES];	/* the last tick's */
	int have_cmd;
	/* the command of tick k at cmd_hist[k % HSC_CMD_HISTORY], for the
	 * last HSC_CMD_HISTORY ticks of a stream (from cmd_hist_from) */
	int32_t cmd_hist[HSC_CMD_HISTORY][SH2000_AXES];
	uint64_t cmd_hist_from;
	int over_ticks;		/* ticks in a row the fill was too far ahead */
	int recentring;		/* catching up a card that slipped */
	/* the fill's readings of this window of HSC_SLIP_TICKS (the low
	 * side's judge), and what the stream still has to add back */
	uint16_t fill_hist[HSC_FILL_BINS];
	int fill_n;
	double raise_left;	/* records */
	/* a queue-target changed while streaming: records still to add
	 * (negative: to leave out), HSC_SLIP_RATE a tick */
	double target_left;
	/* where the stream's first batch landed on the timebase's clock
	 * (records since its reference, taken at tick start_ref), until the
	 * card's start is checked against it (write.c), and the delay
	 * measurements taken since the stream started (feedback.c) */
	double start_clock;
	uint64_t start_ref;
	int start_check;	/* 0: checked, or nothing to check */
	int delay_n;
	/* the snapshot the delay was last measured on; a run of outliers
	 * (feedback.c) */
	uint64_t delay_cycle;
	int delay_cycle_seen;
	double delay_out;
	int delay_out_n;

	struct hsc_index ix[SH2000_AXES];
	uint64_t ix_fail_tick;	/* tick + 1 of the last index failure */

	uint32_t underruns;
	struct sh2000_port_counters pc_last;
	uint32_t port_cycles;
	struct hsc_timebase tb;
	char err[256];
	/* the card's tables: as hsc_comp_load() made them at start, then as
	 * the watch last read them (zero: none) */
	struct sh2000_comp_status comp;
	struct hsc_comp_watch cw;
};

/* Open and check the card (not real-time: at module load). msg gets the
 * reason on failure. */
int hsc_open(struct hsc_card *c, int index, const char *device, char *msg,
	     size_t len);
void hsc_close(struct hsc_card *c);
/* io: devices: the card's four ports for the calling thread (ioperm() is
 * per thread); 0, or -errno. Nothing for other devices. */
int hsc_io_thread(const char *device);
/* Default position-scale of an axis: the card's own scale (counts/mm). */
double hsc_default_scale(struct hsc_card *c, unsigned int axis);
/* comp.c: a table file for the card at start (not real-time). wanted: a
 * path was given ("" and "-": none). check: read and checked against the
 * card's scales and limits, nothing sent; load: through libsh2000's loader,
 * c->comp then holds the card's status of its tables. Both 0 or a
 * negative code with the library's message (FILE:LINE: why) in msg. */
int hsc_comp_wanted(const char *path);
int hsc_comp_check(struct hsc_card *c, const char *path, char *msg, size_t len);
int hsc_comp_load(struct hsc_card *c, const char *path, char *msg, size_t len);
/* After a load: for each soft limit the tables move the tool beyond (the
 * card judges soft limits on nominal positions, then adds the correction:
 * sh2000_comp_reach_file()), say(ctx, words) once with the library's
 * words. The number of warnings (>= 0), or the library's error with its
 * message in msg. Not real-time. */
int hsc_comp_reach(struct hsc_card *c, const char *path,
		   void (*say)(void *ctx, const char *words), void *ctx,
		   char *msg, size_t len);
/* The card's tables read once into the watch's `seen` (not real-time):
 * 0 or the library's error. The watch thread's work, one period. */
int hsc_comp_refresh(struct hsc_card *c);
/* The watch thread, every period_ms (HSC_COMP_WATCH_MS for the module),
 * started after the tables at start are loaded and before the servo
 * thread runs; stopped by hsc_close (and by stop, at once). A card older
 * than protocol 1.5 has no tables to watch: the thread ends at its first
 * read. 0, or a negative code with the reason in msg. */
int hsc_comp_watch_start(struct hsc_card *c, unsigned int period_ms,
			 char *msg, size_t len);
void hsc_comp_watch_stop(struct hsc_card *c);
/* Real-time (the read half): c->comp becomes what the watch last read,
 * when it has read since and its lock is free now. */
void hsc_comp_take(struct hsc_card *c);

/*
 * One servo tick, in two halves: read first in the thread (status,
 * feedback, answers), write last (commands, the point, the thread's
 * correction). period_ns is the thread's period; late_ns how far after its
 * scheduled start the tick runs (0 if unknown).
 */
void hsc_read(struct hsc_card *c, const struct hsc_in *in,
	      struct hsc_out *out, long period_ns, long late_ns);
void hsc_write(struct hsc_card *c, const struct hsc_in *in,
	       struct hsc_out *out);

/* The card's state as the decisions see it: moving (running, stopping,
 * homing), a fault or estop latched, the mask of enabled axes. */
int hsc_moving(unsigned int state);
int hsc_faulted(const struct sh2000_status *st);
unsigned int hsc_enabled(const struct sh2000_status *st);

/* Servo cycles per coarse period for a thread period (write.c). */
int hsc_fine_steps(long period_ns);

/* feedback.c: the delay from command to the card's set-point, measured
 * on a fresh snapshot; position-fb of an axis, in counts. */
double hsc_period_cycles(const struct hsc_card *c);
double hsc_snap_time(const struct hsc_card *c);
void hsc_clock_offset(struct hsc_card *c, long late_ns);
void hsc_delay_update(struct hsc_card *c);
double hsc_feedback_counts(const struct hsc_card *c, unsigned int a);
double hsc_delay_ms(const struct hsc_card *c);

/* index.c: index-enable. hsc_index_read runs in the read half after the
 * command answers (hsc_index_answer takes an INDEX_* one); the offset is
 * the counts position-fb is measured from; hsc_index_command shifts the
 * commands by it (hal_sh2000.c and the tests call it on the pins' values
 * before hsc_read and hsc_write). */
void hsc_index_read(struct hsc_card *c, const struct hsc_in *in);
void hsc_index_answer(struct hsc_card *c, int r, int32_t value);
double hsc_index_offset(const struct hsc_card *c, unsigned int a);
void hsc_index_command(const struct hsc_card *c, struct hsc_in *in);

/* timebase.c */
void hsc_tb_reset(struct hsc_timebase *tb);
/* Every tick, before the heartbeat is read: the clock moves on. */
void hsc_tb_advance(struct hsc_timebase *tb, uint64_t tick);
/* A heartbeat read `late_ns` after the tick's start (a period or more:
 * a missed tick run late, whose reading is not taken). Returns 1 when the
 * card's clock jumped (the reference starts again). */
int hsc_tb_update(struct hsc_timebase *tb, uint64_t tick, uint16_t hb,
		  long late_ns, long period_ns, long servo_ns);

#endif /* HSC_H */
