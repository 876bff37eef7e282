/* SPDX-License-Identifier: MIT */
/*
 * libsh2000: the C library NC applications call to drive an SH-2000TH
 * motion card (docs/library.md is the tour).
 *
 * Error rule: every function that can fail returns an int that is 0 or
 * positive on success and negative on failure: -errno for system errors,
 * -SH2000_E* (SH2000_E_BASE..SH2000_E_LAST) for card and protocol errors.
 * sh2000_strerror() names every code; sh2000_last_error() says what failed
 * and where on this handle.
 *
 * Thread safety: a handle has its own mutex, so threads may share it. Port
 * sequences are bounded and run under the mutex; waits (for a command
 * acknowledgement, queue space, idle) release it between polls, so an
 * emergency stop from another thread never waits behind them. The library
 * has no global mutable state: separate handles are independent.
 *
 * The card's state, fault bits, parameter ids and axis count are the
 * protocol's own names (sh2000/card.h), not copies. Where they live in the
 * dual-port RAM (sh2000/sh2000_protocol.h) is not needed to use this API.
 */
#ifndef SH2000_SH2000_H
#define SH2000_SH2000_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/card.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- errors ---------------------------------------------------------- */

enum sh2000_error {
	SH2000_E_BASE = 1000,
	SH2000_EVERSION = 1000,		/* card speaks another protocol major */
	SH2000_EMAGIC = 1001,		/* no firmware: magic word wrong */
	SH2000_EHEARTBEAT = 1002,	/* card heartbeat stopped (DSP stalled) */
	SH2000_ETIMEOUT = 1003,		/* the card did not answer in time */
	SH2000_EQUEUE_FULL = 1004,	/* no room in the ring for the batch */
	SH2000_EPARAM = 1005,		/* value rejected by host validation */
	SH2000_ETORN = 1006,		/* snapshot kept tearing, retries spent */
	SH2000_ENOTSIM = 1007,		/* needs a simulated card */
	SH2000_ESTOPPED = 1008,		/* the card stopped a motion this
					   handle was streaming (a STOP
					   from another program) */
	SH2000_EOWNED = 1009,		/* another program controls the
					   motion (the message names it) */
	/* command results (SH2000_RES_*) */
	SH2000_ECMD_OP = 1010,		/* card: unknown command */
	SH2000_ECMD_AXIS = 1011,	/* card: bad axis */
	SH2000_ECMD_PARAM = 1012,	/* card: unknown parameter */
	SH2000_ECMD_VALUE = 1013,	/* card: value out of range */
	SH2000_ECMD_BUSY = 1014,	/* card: not allowed while moving */
	SH2000_ECMD_FAULTED = 1015,	/* card: a latched fault forbids it */
	SH2000_ECMD_CHECKSUM = 1016,	/* card: command check word wrong */
	SH2000_ECMD_DISABLED = 1017,	/* card: axis not enabled / not idle */
	SH2000_ECMD_UNKNOWN = 1018,	/* card: result code not in protocol */
	/* latched card faults */
	SH2000_EESTOP = 1020,		/* emergency stop latched */
	SH2000_EUNDERRUN = 1021,	/* ring ran dry mid-motion */
	SH2000_EHOST_TIMEOUT = 1022,	/* card saw the host heartbeat stop */
	SH2000_EREJECTED = 1023,	/* card rejected a segment record */
	SH2000_EPROTOCOL = 1024,	/* card saw an impossible ring fill */
	SH2000_EFAULTED = 1025,		/* card faulted (no known fault bit) */
	/* latched axis faults */
	SH2000_EFERR = 1030,		/* following error limit */
	SH2000_ESOFT_LIMIT = 1031,	/* set-point beyond a soft limit */
	SH2000_EHARD_LIMIT = 1032,	/* limit switch hit */
	SH2000_EDAC_SAT = 1033,		/* DAC saturated too long */
	SH2000_ECOUNTER = 1034,		/* implausible encoder counter jump */
	SH2000_EHOME = 1035,		/* homing failed */
	SH2000_ESKEW = 1036,		/* a gantry pair's skew beyond its
					   limit (protocol 1.7) */
	/* programs and motion (libsh2000-motion) */
	SH2000_EPROGRAM = 1040,		/* error in an NC program (the message
					   gives file:line:column) */
	SH2000_EFORMAT = 1041,		/* not a program format the reader
					   knows */
	SH2000_ELIMIT = 1042,		/* a planned point beyond a soft limit */
	SH2000_EMOVED = 1043,		/* the card moved since the program
					   was checked (the message names the
					   axis) */
	SH2000_EGANTRY = 1044,		/* a motion moves the sides of the
					   card's gantry pair apart */
	/* data gathering (protocol 1.2) */
	SH2000_EGATHER_CHECK = 1050,	/* a chunk of the record kept failing
					   its check (the bus corrupts it) */
	SH2000_EGATHER_LOST = 1051,	/* the record being read was replaced
					   (another program armed a new one) */
	SH2000_E_LAST = 1051,
};

/* Name of any code this library returns (-errno, -SH2000_E*, >= 0). */
const char *sh2000_strerror(int code);

/* ---- handles --------------------------------------------------------- */

struct sh2000;

enum sh2000_backend_kind {
	SH2000_BACKEND_DEV = 0,	/* /dev/sh2000-N, the kernel driver */
	SH2000_BACKEND_IO = 1,	/* io:0xNNN, direct port I/O */
	SH2000_BACKEND_SIM = 2,	/* sim, in-process card model, virtual time */
	SH2000_BACKEND_SHM = 3,	/* sim:NAME, served card model, real time */
	SH2000_BACKEND_PORTS = 4, /* the caller's struct sh2000_ports */
};

#define SH2000_DEFAULT_DEVICE	"/dev/sh2000-0"
#define SH2000_DEVICE_ENV	"SH2000_DEVICE"

/*
 * Open a card. device: "/dev/sh2000-N" (or any path), "io:0xNNN", "sim",
 * "sim:NAME"; NULL or "" means $SH2000_DEVICE, else /dev/sh2000-0. Checks
 * the magic, the protocol version and the heartbeat. On failure *out is
 * NULL and, if msg is not NULL, msg gets a message naming the device and
 * the reason.
 */
int sh2000_open(struct sh2000 **out, const char *device, char *msg,
		size_t msglen);
void sh2000_close(struct sh2000 *h);

/*
 * A card behind the FPGA's four registers (SH2000_REG_* of the register
 * map) that the caller supplies: a card model, a test's fake card, a
 * bridge to other hardware. `sim` is this with libsh2000-sim's model.
 * ctx is handed to every function; now_ns/advance_ns NULL mean real time
 * (CLOCK_MONOTONIC, sleeping). watch may be NULL (sh2000_watch_cycles()).
 */
struct sh2000_cycle;
typedef void (*sh2000_cycle_fn)(void *arg, const struct sh2000_cycle *c);

struct sh2000_ports {
	size_t size;		/* sizeof(struct sh2000_ports) */
	unsigned int flags;	/* SH2000_PORTS_F_* */
	void *ctx;
	void (*out)(void *ctx, unsigned int reg, uint16_t v);
	uint16_t (*in)(void *ctx, unsigned int reg);
	uint64_t (*now_ns)(void *ctx);
	void (*advance_ns)(void *ctx, uint64_t ns);
	int (*watch)(void *ctx, sh2000_cycle_fn fn, void *arg);
	void (*close)(void *ctx);
};

/* The card keeps its own clock: waits advance it (now_ns, advance_ns
 * required) under the handle's lock instead of sleeping. */
#define SH2000_PORTS_F_VIRTUAL_TIME	0x0001u
/* A simulated card: sh2000_backend() says SH2000_BACKEND_SIM. */
#define SH2000_PORTS_F_SIMULATED	0x0002u

/* Open a card on *ports (copied). The handle owns ports->ctx from here on,
 * on failure too: close(ctx) runs at sh2000_close() or before an error
 * return. name is what sh2000_device() reports. */
int sh2000_open_ports(struct sh2000 **out, const struct sh2000_ports *ports,
		      const char *name, char *msg, size_t msglen);
/* Run fn on the handle's ports under the handle's lock (so it is
 * serialised with the library's own port cycles); -SH2000_ENOTSIM if h was
 * not opened on struct sh2000_ports. Returns what fn returns. */
int sh2000_ports_call(struct sh2000 *h,
		      int (*fn)(const struct sh2000_ports *p, void *arg),
		      void *arg);

/*
 * What a simulated card did in one servo cycle: its fine-interpolated
 * set-points and encoder positions (counts, not wrapped). A real card
 * does not show this; traces and tests use it to measure feed and contour
 * where the card produces them.
 */
struct sh2000_cycle {
	uint64_t servo_cycle;	/* servo cycles run so far */
	uint64_t time_ns;	/* card time */
	unsigned int state;	/* enum sh2000_card_state */
	struct {
		double fine_cmd;	/* set-point this cycle, counts */
		double actual;		/* encoder position, counts */
		double velocity;	/* counts/s */
		int16_t dac;		/* DAC code output */
	} axis[SH2000_AXES];
};
/* fn runs after every servo cycle inside the library's calls on h (keep
 * it short; NULL removes it). -SH2000_ENOTSIM unless the card shows its
 * cycles (`sim`). */
int sh2000_watch_cycles(struct sh2000 *h, sh2000_cycle_fn fn, void *arg);

/* What the last failing call on h said. The pointer stays valid until the
 * next call on h; threads sharing h use sh2000_last_error_copy(). */
const char *sh2000_last_error(struct sh2000 *h);
void sh2000_last_error_copy(struct sh2000 *h, char *buf, size_t len);

const char *sh2000_device(const struct sh2000 *h);
enum sh2000_backend_kind sh2000_backend(const struct sh2000 *h);
/* SH2000_W_VERSION as the card reported it at open. */
unsigned int sh2000_card_version(const struct sh2000 *h);

/*
 * Versions of the library that is running (not the one compiled against):
 * "MAJOR.MINOR.PATCH", the SONAME's major (libsh2000.so.N), and the kernel
 * driver's ABI version it speaks (it refuses another at open). The
 * protocol version it speaks is SH2000_PROTO_MAJOR/MINOR.
 */
const char *sh2000_version(void);
unsigned int sh2000_soversion(void);
unsigned int sh2000_driver_abi(void);

/* sh2000_driver_info() flags: the card is sh2000_sim.ko's simulated one */
#define SH2000_DRIVER_SIMULATED	0x0001u
/* What the kernel driver behind h (/dev/sh2000-N) says about itself: its
 * version into version[0..len) (NUL-terminated), its ABI version and
 * SH2000_DRIVER_* flags (either pointer may be NULL). 0; -ENODEV when h
 * is not a /dev/sh2000-N handle (no driver); another -errno when the
 * driver does not answer. */
int sh2000_driver_info(struct sh2000 *h, char *version, size_t len,
		       unsigned int *abi, unsigned int *flags);

/* The handle's clock: virtual card time for `sim`, CLOCK_MONOTONIC else. */
uint64_t sh2000_now_ns(struct sh2000 *h);
/* Let time pass: advances the card model for `sim`, sleeps otherwise. */
int sh2000_sleep_ns(struct sh2000 *h, uint64_t ns);

/* ---- status ---------------------------------------------------------- */

struct sh2000_axis_status {
	int64_t pos_counts;	/* encoder, 28-bit counter extended to 64 */
	int32_t cmd_counts;	/* card's set-point */
	int32_t ferr_counts;	/* cmd - pos */
	double pos_mm, cmd_mm, ferr_mm;
	int16_t dac;		/* DAC code */
	unsigned int state;	/* SH2000_AXIS_* bits */
	unsigned int faults;	/* SH2000_AXIS_FAULT_* bits */
	uint64_t reserved[4];	/* room to grow, zero (see below) */
};

/* The fault that latched first since the last reset (protocol 1.4: the
 * card's first-fault record, docs/protocol.md 10.1). */
struct sh2000_first_fault {
	unsigned int bit;	/* an SH2000_AXIS_FAULT_* bit of `axis`, or
				 * an SH2000_FAULT_* bit; 0: nothing latched,
				 * or a card before 1.4 (sh2000_card_version) */
	unsigned int axis;	/* 0..3, or SH2000_AXIS_GLOBAL: a card fault */
	uint64_t cycle;		/* servo cycle it latched in, counted as
				 * card_cycle */
};

/*
 * Room to grow. The structs a later version may extend (this status, the
 * configs, the stats) end in `reserved`: a new field takes its place in
 * an anonymous union, so the size and every offset stay and a program
 * built against an older header keeps working (docs/install.md, "Versions
 * and the ABI"). The library zeroes it in what it fills, the _default()
 * functions in what they fill; a caller that fills a config by hand
 * starts from zero (= {0}) or from _default(). A new field's 0 means what
 * the library did before it.
 */
struct sh2000_status {
	unsigned int card_state;	/* enum sh2000_card_state */
	unsigned int card_faults;	/* SH2000_FAULT_* bits */
	unsigned int queue_fill;	/* records queued, 0..RING_RECORDS */
	unsigned int queue_free;
	uint16_t heartbeat;		/* card heartbeat word */
	uint64_t heartbeat_age_ns;	/* host time since it last changed */
	uint64_t card_cycle;		/* servo cycle of the snapshot, the
					 * card's 32 bits extended to 64 */
	uint16_t snap_seq;		/* snapshot sequence (SNAP_SEQ_*) */
	uint16_t estop_req, estop_ack;
	uint16_t reject_seq, reject_reason, reject_count;
	uint64_t host_time_ns;		/* sh2000_now_ns() at the poll */
	unsigned int retries;		/* torn snapshots re-read */
	struct sh2000_axis_status axis[SH2000_AXES];
	/* Appended in protocol 1.4: which of the latched faults came
	 * first; sh2000_status_error() names it. */
	struct sh2000_first_fault first_fault;
	uint64_t reserved[16];		/* room to grow, zero */
};

/* A card heartbeat unchanged for this long is a stopped DSP (or five
 * servo periods, when the card is set to run slower than 500 Hz). */
#define SH2000_HEARTBEAT_LIMIT_NS	10000000ull
/* The same for `sim:NAME`, whose DSP is an ordinary process. */
#define SH2000_HEARTBEAT_LIMIT_SHM_NS	100000000ull
/* Change the limit for this handle (0: back to the rule above), e.g. for
 * a `sim:NAME` card served on a loaded machine. */
void sh2000_set_heartbeat_limit(struct sh2000 *h, uint64_t ns);
/* Torn snapshots re-read at once; after these a poll keeps re-reading
 * every 20 us. Inside one publication for a tenth of the heartbeat limit
 * while the card heartbeat moves on, it gives up with SH2000_ETORN; with
 * the heartbeat standing still for the limit, with SH2000_EHEARTBEAT. */
#define SH2000_POLL_RETRIES		16

/*
 * One poll: words 0..SH2000_STATUS_WORDS-1 in one streamed read (re-read
 * while the snapshot is torn), then the host heartbeat. Fills *st and
 * returns 0; -SH2000_EHEARTBEAT (with *st filled) when the card heartbeat
 * has not advanced for SH2000_HEARTBEAT_LIMIT_NS. Latched faults are in
 * *st, not in the return value (see sh2000_status_error()). The first
 * poll that finds a fault latched on a 1.4 card also reads the card's
 * first-fault record (words 832..836, 794 port cycles more, once per
 * fault and again after a command while it stays latched).
 */
int sh2000_poll(struct sh2000 *h, struct sh2000_status *st);
/* The error a status' latched faults stand for (0 if none), with the
 * detail message set on h: the first fault (st->first_fault) of a card
 * from protocol 1.4; on an older card, which keeps no order of its
 * faults, an emergency stop, then axis faults (axis 0 first), then a
 * rejected record, host timeout, underrun, protocol fault. */
int sh2000_status_error(struct sh2000 *h, const struct sh2000_status *st);
/* Whether a status shows the card faulted: a fault latched on the card or
 * an axis, or the card in FAULT or ESTOP (exactly when
 * sh2000_status_error() is not 0). A pure function of *st, safe in a
 * real-time thread; the one definition every front end uses. */
int sh2000_status_faulted(const struct sh2000_status *st);

/* ---- commands -------------------------------------------------------- */

/* Default wait for a command acknowledgement. */
#define SH2000_CMD_TIMEOUT_MS	100

/* One raw command (enum sh2000_cmd_op): waits for the acknowledgement;
 * result codes map to -SH2000_ECMD_*; *value gets CMD_VALUE if not NULL. */
int sh2000_command(struct sh2000 *h, unsigned int op, unsigned int axis,
		   unsigned int param, int32_t arg, int32_t *value);
int sh2000_nop(struct sh2000 *h);
int sh2000_enable(struct sh2000 *h, unsigned int axis_mask);
int sh2000_disable(struct sh2000 *h, unsigned int axis_mask);
/* Controlled stop: the card decelerates and discards the ring. */
int sh2000_stop(struct sh2000 *h);
/* Clear latched faults (and a latched emergency stop); card goes idle. */
int sh2000_reset(struct sh2000 *h);
/* Home one axis (flags: SH2000_HOME_F_*); poll or wait_idle for the end. */
int sh2000_home(struct sh2000 *h, unsigned int axis, unsigned int flags);
/* Tell the card axis is at pos_mm now. */
int sh2000_set_position(struct sh2000 *h, unsigned int axis, double pos_mm);
/*
 * Emergency stop: writes SH2000_W_ESTOP_REQ at once (never behind a
 * command or the ring), then waits up to timeout_ms for ESTOP_ACK.
 */
int sh2000_estop(struct sh2000 *h, int timeout_ms);

/* ---- the index latch while a stream runs (protocol 1.6) ------------- */

/* What became of an axis' last INDEX_ARM (docs/library.md "Index"). */
struct sh2000_index {
	unsigned int state;	/* enum sh2000_index_state */
	unsigned int arm;	/* the arm it answers (sh2000_index_arm's) */
	int64_t counts;		/* LATCHED: the encoder at the mark, as
				 * sh2000_axis_status.pos_counts counts */
	double mm;		/* the same in mm (the card's scale) */
	uint64_t cycle;		/* LATCHED: the servo cycle that found it,
				 * as sh2000_status.card_cycle counts */
};

/* 0 when the card has the index arm (protocol 1.6), else -EOPNOTSUPP
 * with the card's version and the one needed in sh2000_last_error(). */
int sh2000_index_supported(struct sh2000 *h);
/* Arms axis' index latch (flags: SH2000_INDEX_F_*), with or without a
 * stream running; the next mark the flags let through is latched. An
 * axis that travels more than within_mm (0: no limit) from here without
 * one ends MISSED. Returns the arm's number (>= 0) or an error. */
int sh2000_index_arm(struct sh2000 *h, unsigned int axis, unsigned int flags,
		     double within_mm);
int sh2000_index_disarm(struct sh2000 *h, unsigned int axis);
/* The axis' index block, read once (a real-time call: no wait, -EAGAIN
 * when the read was torn or the handle busy; read again later). st: a
 * status read just before, which the mark's counter is extended by. */
int sh2000_index_read(struct sh2000 *h, unsigned int axis,
		      const struct sh2000_status *st, struct sh2000_index *ix);

/* ---- several programs on one card ----------------------------------- */

/*
 * Any number of programs may open one card (dev, io:, sim:NAME) and send
 * commands at once: each exchange holds the card's command lock, so every
 * answer goes to the program that asked. The motion belongs to one program
 * at a time: the first sh2000_push_*() claims it (or sh2000_claim_motion()
 * does, before enabling); while a program holds it, the others' enable,
 * disable, home, set_position and reset fail with -SH2000_EOWNED and a
 * message naming the holder. Status, parameters, nop and STOP stay open to
 * all, and sh2000_estop() never waits for anyone. The claim ends with
 * sh2000_release_motion(), sh2000_close() or the holder's death. An
 * in-process `sim` card belongs to its handle alone. docs/library.md.
 */
int sh2000_claim_motion(struct sh2000 *h);
void sh2000_release_motion(struct sh2000 *h);
/* 1 and "name (pid N)" in buf if a program (this one included) holds the
 * motion, 0 if none does. */
int sh2000_motion_holder(struct sh2000 *h, char *buf, size_t len);

/* ---- parameters ------------------------------------------------------ */

/* axis argument for the global parameters (SH2000_GP_*) */
#define SH2000_GLOBAL		(-1)

/*
 * Parameters in user units: lengths in mm (ferr_limit, soft_min/max,
 * home_offset), velocities mm/s (vmax, home_vel), accelerations mm/s^2
 * (amax); scale counts/mm; gains, times, DAC values, cycles and the global
 * parameters in the card's units. Conversion uses the axis' scale as the
 * library last read or set it.
 *
 * Validation happens before anything is written: NaN or infinity, values
 * outside the protocol's range (negative gains...), soft limits out of
 * order, values the card cannot represent, soft limits that would leave an
 * enabled or homed axis outside them (sh2000_soft_limits_check(), judged
 * on a poll of the card) -> -SH2000_EPARAM with a message naming the axis
 * and the parameter.
 */
int sh2000_param_set(struct sh2000 *h, int axis, unsigned int param,
		     double value);
int sh2000_param_get(struct sh2000 *h, int axis, unsigned int param,
		     double *value);
/* Parameter names as users see them; -SH2000_EPARAM if unknown. */
int sh2000_param_id(const char *name);
const char *sh2000_param_name(unsigned int param);
const char *sh2000_param_unit(unsigned int param);
/*
 * Whether value v (in the parameter's user unit: mm for the ones the card
 * keeps in counts, which scale converts) can go to the card: 0 and the
 * value the card will hold in *card (counts, or rounded to a binary32),
 * or -SH2000_EPARAM with the reason in why, e.g. "2000 DAC/count is
 * outside 0..1000 DAC/count". sh2000_param_set() refuses with the same
 * reason after "axis N parameter NAME: ", and every front end (sh2000ctl,
 * Python) prints it: one rule, one wording. Reads no card.
 */
int sh2000_param_value_check(unsigned int param, double v, double scale,
			     double *card, char *why, size_t len);
/*
 * Whether soft limits soft_min..soft_max mm, with scale counts/mm (the
 * card keeps them in counts: mm * scale rounded, as
 * sh2000_param_value_check() converts them), keep axis `axis` (0..3) of
 * status st inside them where its position counts: an enabled axis' set-
 * point (cmd_counts), a homed axis' position (pos_counts); a disabled
 * axis never homed is not judged. The card refuses every set-point
 * outside its soft limits, so an axis left outside could not move at
 * all, not even back. 0, or -SH2000_EPARAM with the reason in why, e.g.
 * "x soft limits 50..200 mm would leave axis x (enabled, at 10.0000 mm)
 * outside them: the card refuses every set-point outside its soft limits,
 * so nothing could move it back; move it inside first, or give limits
 * around it". sh2000_param_set() and sh2000_axis_params_set() refuse new
 * soft limits with it (after "axis x parameter NAME: "), and sh2000ctl
 * judges its plans with it: one rule, one wording. Reads no card: st is
 * from sh2000_poll(). A new scale alone moves nothing (the card keeps
 * limits and position in counts); with new limits, pass the new scale.
 */
int sh2000_soft_limits_check(const struct sh2000_status *st, unsigned int axis,
			     double soft_min, double soft_max, double scale,
			     char *why, size_t len);

/*
 * The card's timing: coarse_period_us and fine_steps changed together
 * through legal states (sh2000_timing_ok() after every single set; the
 * card checks each against the other's current value). Of the paths
 * sh2000_set_timing() takes one whose states in between keep the servo
 * period within the longer of the old and the new where there is one
 * (the loops then never run slower than at either end). The target is
 * checked first: -SH2000_EPARAM with the reason, nothing sent. A failure
 * half-way leaves the card at a legal state on the way.
 */
int sh2000_set_timing(struct sh2000 *h, unsigned int coarse_us,
		      unsigned int fine_steps);

/* One set of that path: SH2000_GP_COARSE_PERIOD_US or SH2000_GP_FINE_STEPS
 * and its value. */
struct sh2000_timing_step {
	unsigned int id;
	unsigned int value;
};
#define SH2000_TIMING_STEPS_MAX	16
/* only states whose servo period is within the longer of the two ends */
#define SH2000_TIMING_NO_LONGER	0x0001u
/* The path itself, without a card (a real-time caller sends the steps
 * itself): the fewest sets from (coarse0_us, fine0) to (coarse_us,
 * fine_steps), each leaving a legal state in the protocol's ranges, into
 * steps[0..max). coarse0_us 0: the card's coarse period is not known (the
 * first step then sets it to a value legal with fine0; from fine0 1 every
 * value is). The number of steps (0: already there), or -SH2000_EPARAM
 * when the target is not legal or no path of at most max steps exists. */
int sh2000_timing_path(unsigned int coarse0_us, unsigned int fine0,
		       unsigned int coarse_us, unsigned int fine_steps,
		       unsigned int flags, struct sh2000_timing_step *steps,
		       unsigned int max);

/* Every per-axis parameter, indexed by enum sh2000_param, in user units. */
struct sh2000_axis_params {
	double v[SH2000_AXIS_PARAMS];
};
/* The protocol's defaults, in user units. */
void sh2000_axis_params_default(struct sh2000_axis_params *p);
int sh2000_axis_params_get(struct sh2000 *h, unsigned int axis,
			   struct sh2000_axis_params *p);
/* Validates all of p (scale first, the rest in the new scale; the soft
 * limits against the axis' position, sh2000_soft_limits_check()), then
 * sets them: nothing is sent if any value is bad. */
int sh2000_axis_params_set(struct sh2000 *h, unsigned int axis,
			   const struct sh2000_axis_params *p);

/* ---- segments -------------------------------------------------------- */

/* sh2000_push_*() flags */
#define SH2000_PUSH_END		0x0001u	/* last batch of a motion */

/*
 * Queue n coarse-interpolation points (one record each, all axes) in one
 * all-or-nothing batch: either all n are queued and published with one
 * HEAD update, or nothing is written. Returns n, -SH2000_EQUEUE_FULL if
 * the ring has not room for all n now, -EMSGSIZE if n > ring size, a
 * latched card fault as its error, -SH2000_EPARAM for an unrepresentable
 * point. Each record carries the segment number sh2000_next_segment()
 * gives (low 16 bits); a rejection names it.
 */
int sh2000_push_counts(struct sh2000 *h, const int32_t (*pts)[SH2000_AXES],
		       size_t n, unsigned int flags);
int sh2000_push_mm(struct sh2000 *h, const double (*pts)[SH2000_AXES],
		   size_t n, unsigned int flags);
uint64_t sh2000_next_segment(struct sh2000 *h);
/* Records the card's ring holds (the most sh2000_push_*() takes at once). */
unsigned int sh2000_queue_size(const struct sh2000 *h);
/* Free records in the ring now (one read), or an error. */
int sh2000_queue_free(struct sh2000 *h);
/* Wait until n records fit / the card is idle with an empty ring (and has
 * published a snapshot since, so a poll shows the end of the motion). A
 * latched fault ends the wait with its error; -SH2000_ETIMEOUT after
 * timeout_ms (negative: no limit). Waits keep the host heartbeat going. */
int sh2000_wait_space(struct sh2000 *h, unsigned int n, int timeout_ms);
int sh2000_wait_idle(struct sh2000 *h, int timeout_ms);
/* Wait until the card is at rest: not moving as sh2000_state_moving()
 * says (after a STOP it ends IDLE; FAULT and ESTOP are at rest too). A
 * latched fault does not end the wait: the caller of a stop wants the
 * card at rest whatever latched, and reads the faults itself. Polls,
 * which keeps the host heartbeat going; -SH2000_ETIMEOUT after
 * timeout_ms (negative: no limit), the message naming the state. */
int sh2000_wait_rest(struct sh2000 *h, int timeout_ms);

/* ---- calls for a real-time thread: they never wait ------------------- */

/*
 * For a periodic real-time thread (a LinuxCNC servo thread): none of these
 * sleeps, retries, or waits for a lock, and each is one bounded port
 * sequence. What cannot be done now returns -EAGAIN ("try next tick") and
 * changes nothing. docs/library.md "Real-time calls".
 */

/*
 * One status read: words 0..46 streamed once, then the host heartbeat.
 * 0: *st is a consistent status. -EAGAIN: the snapshot was torn by a
 * publication (or the handle is busy in another thread): *st is left
 * as it was, read again next tick. -SH2000_EHEARTBEAT (with *st filled)
 * when the card heartbeat has not advanced for the handle's limit,
 * -SH2000_EMAGIC when the firmware is gone. A started command's answer is
 * kept for sh2000_command_complete().
 */
int sh2000_poll_once(struct sh2000 *h, struct sh2000_status *st);

/*
 * Start one command (enum sh2000_cmd_op) and return without waiting: 0
 * when it is written. -EAGAIN: the command slot is in use by another
 * thread or program; -EBUSY: this handle's last started command has not
 * completed yet; -SH2000_EOWNED: a command that changes the motion while
 * another program holds it. The card's command slot stays this handle's
 * until sh2000_command_complete() returns something else than
 * -EINPROGRESS or -EAGAIN.
 */
int sh2000_command_start(struct sh2000 *h, unsigned int op,
			 unsigned int axis, unsigned int param, int32_t arg);
/*
 * The answer to the started command: 0 (and *value if not NULL) when the
 * card answered OK, -SH2000_ECMD_* for its result code, -EINPROGRESS while
 * it has not answered, -SH2000_ETIMEOUT (or -SH2000_EHEARTBEAT for a
 * stopped card) after SH2000_CMD_TIMEOUT_MS, -EINVAL if none was started.
 * Uses the words the last sh2000_poll_once() read when it ran after the
 * start (no port cycles), else reads the four answer words.
 */
int sh2000_command_complete(struct sh2000 *h, int32_t *value);

/*
 * Queue one point (counts) as the next record, with flags SH2000_PUSH_*,
 * without reading the card first: the room is what the last
 * sh2000_poll_once() saw (the card only frees records, so that is a lower
 * bound; sh2000_open() polls once). Returns 1; -SH2000_EQUEUE_FULL when
 * that poll saw no room; -EAGAIN when the handle is busy in another
 * thread; -SH2000_EOWNED unless this handle holds the motion
 * (sh2000_claim_motion() first).
 */
int sh2000_push_point(struct sh2000 *h, const int32_t pt[SH2000_AXES],
		      unsigned int flags);

/* Emergency stop request (word 0 changed, 2 port cycles) without waiting
 * for the acknowledgement: a later poll shows state ESTOP. -EAGAIN if the
 * handle is busy in another thread. */
int sh2000_estop_request(struct sh2000 *h);

/* ---- data gathering (protocol 1.2) ---------------------------------- */

/*
 * The card records chosen signals of each axis every `period` servo cycles
 * into its own memory (docs/protocol.md section 17, docs/library.md);
 * afterwards the record is read out in chunks, each one command exchange
 * checked end to end, so other programs' commands go on in between. The
 * signals (enum sh2000_gather_signal) are in the card's units: counts, DAC
 * codes, counts/s.
 */
struct sh2000_gather_config {
	unsigned int signals[SH2000_AXES];	/* per axis: 1u << SH2000_GS_* */
	unsigned int period;		/* servo cycles per sample, 1..65535 */
	uint32_t samples;		/* samples in the record, >= 1 */
	unsigned int trigger;		/* enum sh2000_gather_trigger */
	uint32_t pretrigger;		/* samples kept from before it */
	uint64_t reserved[4];		/* room to grow, zero */
};

/* No signals, period 1, 1000 samples, trigger now, no pre-trigger. */
void sh2000_gather_config_default(struct sh2000_gather_config *c);

struct sh2000_gather_info {
	unsigned int state;		/* enum sh2000_gather_state */
	unsigned int record;		/* the record's number */
	unsigned int trigger, period;
	unsigned int values;		/* values per sample */
	unsigned int signals[SH2000_AXES];
	uint32_t samples;		/* in the record now */
	uint32_t capacity;		/* samples it was armed for */
	uint32_t pretrigger;
	uint32_t trigger_index;		/* first sample at/after the trigger;
					   SH2000_GATHER_NO_TRIGGER if none */
	uint32_t first_cycle;		/* card servo cycle of sample 0 */
	uint32_t trigger_cycle;		/* cycle the trigger fired in */
	uint32_t buffer;		/* the card's memory, 32-bit values */
	double sample_s;		/* period in seconds, at the servo
					   period the handle knows */
	uint64_t reserved[4];		/* room to grow, zero */
};

/*
 * Configure and arm a record (every field sent, then GATHER_ARM, in one
 * hold of the command slot). Returns the record's number (>= 0).
 * -SH2000_EPARAM before anything is sent when c is bad (the message names
 * the field); -EOPNOTSUPP on a card older than protocol 1.2;
 * -SH2000_ECMD_BUSY while a record is armed or recording (stop it first).
 */
int sh2000_gather_start(struct sh2000 *h, const struct sh2000_gather_config *c);
/* End the record now (what it holds stays readable). */
int sh2000_gather_stop(struct sh2000 *h);
/* The card's description of the record (or of its configuration). */
int sh2000_gather_info(struct sh2000 *h, struct sh2000_gather_info *gi);
/* Wait until record number `record` is DONE, polling the card (so its
 * host heartbeat goes on through a motion; latched faults do not end the
 * wait, a record may be triggered by one); *gi then describes it.
 * -SH2000_ETIMEOUT after timeout_ms (< 0: no limit), -SH2000_EGATHER_LOST
 * if a new record replaced it, -SH2000_EHEARTBEAT for a stopped card. */
int sh2000_gather_wait(struct sh2000 *h, unsigned int record,
		       struct sh2000_gather_info *gi, int timeout_ms);
/*
 * Samples [first, first + n) of the record gi describes, as doubles,
 * sample after sample: out[(s - first) * gi->values + k]. Returns n.
 * -EINVAL beyond gi->samples; -SH2000_EGATHER_LOST when another record
 * replaced it; -SH2000_EGATHER_CHECK when a chunk failed its check word
 * three times.
 */
int sh2000_gather_read(struct sh2000 *h, const struct sh2000_gather_info *gi,
		       uint32_t first, uint32_t n, double *out);
/* Which axis and signal value k of a sample is: 0, or -EINVAL if
 * k >= values (the layout: axis 0..3, each in ascending signal order). */
int sh2000_gather_column(const struct sh2000_gather_info *gi, unsigned int k,
			 unsigned int *axis, unsigned int *signal);

/* ---- compensation tables (protocol 1.5) ----------------------------- */

/*
 * Tables on the card that correct each servo cycle's set-point for the
 * machine's geometry: pitch (an axis' own position), straightness (another
 * axis'), squareness (a coefficient per pair), flatness (a grid over two
 * axes). The host's path stays nominal. docs/compensation.md has the file
 * format, the calibration and the order of corrections.
 */
#include "sh2000/comp.h"

/* The card's active tables (status words, protocol.md section 18). */
struct sh2000_comp_status {
	unsigned int state;		/* enum sh2000_comp_state */
	unsigned int tables;		/* tables active */
	uint32_t id;			/* the image's identity */
	uint32_t sum;			/* its sh2000_comp_sum() */
	unsigned int generation;	/* switches since power-up, mod 2^16 */
	uint64_t reserved[2];		/* room to grow, zero */
};

int sh2000_comp_status(struct sh2000 *h, struct sh2000_comp_status *st);
/*
 * Send an image (sh2000/comp.h) in pages and switch to it, in one hold of
 * the command slot. -EOPNOTSUPP on a card older than 1.5; the card's
 * refusal (-SH2000_ECMD_VALUE, -SH2000_ECMD_CHECKSUM) with *fault saying
 * which table and point (fault may be NULL); -SH2000_ECMD_BUSY while the
 * card moves or is still blending from the last switch. A refusal
 * changes nothing that is active. Returns when the card's blend to the
 * new tables (SH2000_COMP_BLEND_MS) has ended.
 */
int sh2000_comp_load_image(struct sh2000 *h, const uint16_t *w, size_t n,
			   struct sh2000_comp_fault *fault);
/* No tables (blended out at rest; returns when the blend has ended). */
int sh2000_comp_clear(struct sh2000 *h);
/* The axes' limits the card checks tables against, from its parameters
 * (counts/s, counts/s^2). */
int sh2000_comp_limits_get(struct sh2000 *h, struct sh2000_comp_limits *lim);

/* A table file (docs/compensation.md) read into an image; every table and
 * point keeps the line it came from. */
struct sh2000_comp_file;

/* Read `path` with the axes' scales (counts per mm). 0, or
 * -SH2000_EPARAM with "FILE:LINE: why" in msg; -errno when unreadable. */
int sh2000_comp_file_read(struct sh2000_comp_file **out, const char *path,
			  const double scale[SH2000_AXES], char *msg,
			  size_t len);
void sh2000_comp_file_free(struct sh2000_comp_file *f);
const uint16_t *sh2000_comp_file_image(const struct sh2000_comp_file *f,
				       size_t *words);
/* The line of table `table`'s point `point` (-1: the table's own line). */
unsigned int sh2000_comp_file_line(const struct sh2000_comp_file *f,
				   int table, int point);
/* "FILE:LINE: table N (KIND): why" for a fault, into msg; returns msg. */
const char *sh2000_comp_file_explain(const struct sh2000_comp_file *f,
				     const struct sh2000_comp_fault *why,
				     char *msg, size_t len);
/* The file checked against limits: 0, or -SH2000_EPARAM and msg. */
int sh2000_comp_file_check(const struct sh2000_comp_file *f,
			   const struct sh2000_comp_limits *lim, char *msg,
			   size_t len);
/* Read `path` with the card's scales and check it against the card's
 * limits, as sh2000_comp_load_file() does, without sending anything: 0,
 * or the same error and message (sh2000_last_error, FILE:LINE when a
 * table is at fault) the loader would give. The card is not changed; a
 * caller with several cards checks every file before loading any. */
int sh2000_comp_check_file(struct sh2000 *h, const char *path);
/* Read `path` with the card's scales, check it against the card's limits
 * (sh2000_comp_check_file()) and load it: 0, or an error whose message (sh2000_last_error) names
 * FILE:LINE when a table is at fault. Nothing changes on a refusal. */
int sh2000_comp_load_file(struct sh2000 *h, const char *path);
/* How far the tables of `path` (read with the card's scales) move each
 * axis inside the card's soft limits, and where a corrected position at
 * a soft limit lies beyond it (sh2000_comp_reach(), sh2000/comp.h; *win
 * is the card's soft limits and scales it was judged with). The number of
 * axes a table corrects (>= 0), or an error whose message
 * (sh2000_last_error) names the file. Nothing is sent. */
int sh2000_comp_reach_file(struct sh2000 *h, const char *path,
			   struct sh2000_comp_window *win,
			   struct sh2000_comp_reach reach[SH2000_AXES]);

/* ---- raw access, for tools and tests --------------------------------- */

struct sh2000_port_counters {
	uint64_t clears, increments, data_reads, data_writes;
	uint32_t position;	/* counter position, 0xffffffff unknown */
};
/* Port cycles this handle issued (dev: the driver's counters for the
 * card). */
int sh2000_port_counters(struct sh2000 *h, struct sh2000_port_counters *c);
/* The dual-port RAM's size in 16-bit words, for programs that do not see
 * the driver's register map (driver/sh2000_hw.h's SH2000_RAM_WORDS; the
 * library checks that the two agree when it is built). */
#define SH2000_DPRAM_WORDS	1024u
/* Words [addr, addr+n) of the dual-port RAM (no wrap past 1023). */
int sh2000_ram_read(struct sh2000 *h, unsigned int addr, unsigned int n,
		    uint16_t *buf);
int sh2000_ram_write(struct sh2000 *h, unsigned int addr, unsigned int n,
		     const uint16_t *buf);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_SH2000_H */
