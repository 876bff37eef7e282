/* SPDX-License-Identifier: MIT */
/*
 * The simulated SH-2000TH card in three layers (docs/cardmodel.md): the DSP
 * firmware (protocol v1, fine interpolation, PID); the board it sees only
 * through FPGA registers (28-bit encoder counters, index latches, switch
 * inputs, DAC outputs) and the dual-port RAM, with its oscillator; and
 * behind the board a plant per axis (linear motor, switches, scale).
 *
 * Two ways to use it:
 *  - sh2000_cardsim_*: a whole card in virtual time, driven through the four
 *    FPGA registers. Each port access costs SH2000_PORT_CYCLE_NS of card time
 *    and runs the servo cycles that time crosses; sh2000_cardsim_advance()
 *    is how a waiting host lets time pass. Deterministic, not thread-safe
 *    (the caller serialises).
 *  - sh2000_fw_* + a RAM the firmware does not own (shared memory, the
 *    kernel sh2000_sim card's DSP side, or a thread in a stress test): the
 *    caller runs sh2000_fw_cycle() once per servo period in real time. All
 *    RAM accesses are 16-bit atomic loads/stores (sh2000_dpram_*), so the
 *    host may poke the RAM concurrently, as on the real dual-port RAM.
 */
#ifndef SH2000_CARDSIM_H
#define SH2000_CARDSIM_H

#include <stdint.h>

#include "sh2000/card.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- plant and environment of one axis (documented defaults) ---- */

struct sh2000_plant_config {
	double mass_kg;			/* moving mass */
	double friction_ns_per_m;	/* viscous friction N/(m/s) */
	double force_n_per_v;		/* force constant incl. amplifier, N/V */
	double counts_per_mm;		/* encoder scale (10 nm = 100000/mm) */
	double limit_neg_mm, limit_pos_mm;	/* hard limit switch positions */
	double home_mm;			/* home switch: active at x <= home_mm */
	double index_period_mm;		/* encoder index spacing, 0: none */
	double start_mm;		/* position at power-up */
	/* Addition: the home switch chatters (toggles every 3 servo
	 * periods) while |x - home_mm| < home_bounce_mm; 0 = clean. */
	double home_bounce_mm;
	/* Addition: the scale's index marks are at index_pos_mm + k *
	 * index_period_mm, each index_width_mm wide (its signal is active
	 * from there to there + width; 0: an edge only, rising and falling
	 * at one count). Distance-coded marks are not modelled. */
	double index_pos_mm;
	double index_width_mm;
};

/*
 * Addition: the machine's geometric errors (docs/cardmodel.md "Geometry").
 * x_a is the carriage of axis a along its guide, in mm from the machine's
 * zero (the plant's position). Each axis' scale reads
 *   x + pitch_slope (x - pitch_ref_mm) + sum_k pitch_amp_mm sin(2 pi x /
 *   pitch_period_mm + pitch_phase)
 * (its graduations, the index marks among them, are where it reads them);
 * the tool, as a laser interferometer measures it, is at
 *   X = x_X + squareness_xy x_Y + straight_y_mm b(x_Y)
 *   Y = x_Y + straight_x_mm b(x_X)
 *   Z = x_Z + flat_mm (b(x_X) + b(x_Y)) / 2 + flat_twist_mm s(x_X) s(x_Y)
 *   A = x_A
 * with the bow b(x) = 4 u (1 - u) and s(x) = 2 u - 1, u = (x - travel_lo_mm)
 * / (travel_hi_mm - travel_lo_mm). All zero: a perfect machine, which is
 * what a card model is until sh2000_fw_set_geometry() (or
 * sh2000_sim_set_geometry()) gives it another.
 */
#define SH2000_PITCH_TERMS	2u

struct sh2000_geometry {
	double pitch_slope[SH2000_AXES];	/* mm per mm */
	double pitch_ref_mm[SH2000_AXES];
	double pitch_amp_mm[SH2000_AXES][SH2000_PITCH_TERMS];
	double pitch_period_mm[SH2000_AXES][SH2000_PITCH_TERMS];	/* > 0 */
	double pitch_phase[SH2000_AXES][SH2000_PITCH_TERMS];	/* rad */
	double squareness_xy;		/* rad: Y's guide leans towards +X */
	double straight_x_mm;		/* X's guide: bow in Y */
	double straight_y_mm;		/* Y's guide: bow in X */
	double flat_mm, flat_twist_mm;	/* the XY plane in Z */
	double travel_lo_mm, travel_hi_mm;
};

struct sh2000_sim_config {
	struct sh2000_plant_config axis[SH2000_AXES];
};

/* Fills *cfg with the documented defaults. */
void sh2000_sim_config_default(struct sh2000_sim_config *cfg);
/* Addition: a perfect machine's geometry (all zero); the default machine
 * with errors (about 10 um of pitch error over 300 mm, 50 urad
 * squareness, a few um of straightness and flatness). */
void sh2000_geometry_none(struct sh2000_geometry *g);
void sh2000_geometry_default(struct sh2000_geometry *g);
/* Addition: where the tool is (mm, machine frame) with carriages at x[]:
 * what the simulated interferometer reads. */
void sh2000_geometry_tool(const struct sh2000_geometry *g,
			  const double x[SH2000_AXES], double tool[SH2000_AXES]);
/* Addition: what axis a's scale reads (mm) with its carriage at x. */
double sh2000_geometry_scale(const struct sh2000_geometry *g, unsigned int a,
			     double x);

/* ---- a gantry (addition): two axes drive one beam ---- */

/* Two axes' motors (sides a and b) carry one beam, joined to it with a
 * finite yaw stiffness: a difference of their positions is a yaw of the
 * beam that the joints resist with a spring and a damper. A carriage (the
 * load) runs along the beam on a third axis; where it is decides how much
 * of its mass each side carries. Uncoupled loops on the two sides then
 * leave a yaw under acceleration and under an asymmetric load. */
struct sh2000_gantry_config {
	unsigned int side_a, side_b;	/* the two motors' axes, a != b */
	int carriage_axis;		/* the axis along the beam, or -1 */
	double beam_kg;			/* the beam, half on each side */
	double carriage_kg;		/* the carriage and its load */
	double span_mm;			/* from side a to side b, > 0 */
	/* the carriage's distance from side a when its axis is at 0 mm;
	 * without a carriage axis, where it stays */
	double carriage_at0_mm;
	double stiffness_n_per_m;	/* yaw: force per m of a - b, >= 0 */
	double damping_ns_per_m;	/* and per m/s of it, >= 0 */
};

/* The documented defaults (docs/cardmodel.md "Gantry"): sides y and z
 * (axes 1 and 2), the carriage on x over 600 mm. */
void sh2000_gantry_config_default(struct sh2000_gantry_config *g);

/* ---- fault injection ---- */

/* Each acts on the hardware or on the firmware's scheduling, never on the
 * firmware's state; the firmware reacts as it would to the real fault. */
enum sh2000_inject {
	SH2000_INJECT_NONE = 0,
	/* the RAM cell HEARTBEAT no longer takes the firmware's writes */
	SH2000_INJECT_HEARTBEAT_STOP,
	/* the firmware gets no servo interrupt for `arg` cycles (0: until
	 * SH2000_INJECT_CLEAR); the board runs on, the DAC holds */
	SH2000_INJECT_DSP_STALL,
	/* XOR bits into a RAM word once: arg = word | mask << 16 (mask 0:
	 * 0x0010) */
	SH2000_INJECT_RAM_FLIP,
	SH2000_INJECT_JAM,		/* the carriage of axis does not move */
	/* a limit switch input of axis reads active (arg 0: -, else +) */
	SH2000_INJECT_LIMIT,
	/* the host's write of its next record (number HEAD) does not reach
	 * the RAM: the slot keeps its old words */
	SH2000_INJECT_DROP_SEGMENT,
	SH2000_INJECT_CLEAR,		/* undo every injection */
	/* Addition: the axis' 28-bit counter jumps by (int32_t)arg counts
	 * once (0: 2^20), as after a glitch on the scale lines. */
	SH2000_INJECT_COUNTER_GLITCH,
};

/* What the card is doing inside, for tests, traces and benchmarks: not
 * visible to a real host. Positions in counts. */
struct sh2000_probe_axis {
	double fine_cmd;	/* fine-interpolated set-point this cycle */
	double actual;		/* encoder position (extended, not wrapped) */
	double velocity;	/* plant velocity, counts/s */
	int16_t dac;		/* DAC code output this cycle */
};

struct sh2000_probe {
	uint64_t servo_cycle;	/* servo cycles run so far */
	uint64_t time_ns;	/* card time */
	unsigned int state;	/* enum sh2000_card_state */
	struct sh2000_probe_axis axis[SH2000_AXES];
};

/* ---- firmware on an external RAM (real time) ---- */

struct sh2000_fw;	/* fixed size; allocated once by sh2000_fw_create() */

/* Only the RAM is shared: sh2000_fw_inject(), _probe() and _set_observer()
 * touch the firmware's own state, so call them from the thread that runs
 * sh2000_fw_cycle() or with the cycles held off (a lock around both). */

int sh2000_fw_create(struct sh2000_fw **out, uint16_t *ram,
		     const struct sh2000_sim_config *cfg);
void sh2000_fw_destroy(struct sh2000_fw *fw);
/* One servo cycle: read host words, interpolate, PID, plant, publish. */
void sh2000_fw_cycle(struct sh2000_fw *fw);
/* Servo period currently configured (coarse period / fine steps), in the
 * card's own time. */
uint64_t sh2000_fw_servo_period_ns(const struct sh2000_fw *fw);
/*
 * Addition: the card oscillator's error. A servo period then lasts
 * nominal * (1 + ppm * 1e-6) of host time: ppm > 0 is a slow card, fewer
 * cycles per host second. |ppm| <= 100000, else -22 and nothing changes.
 * The card's own time (probe time_ns, snapshot TIME) still counts nominal
 * periods; the plant moves in host time.
 */
int sh2000_fw_set_clock_ppm(struct sh2000_fw *fw, double ppm);
double sh2000_fw_clock_ppm(const struct sh2000_fw *fw);
int sh2000_fw_inject(struct sh2000_fw *fw, enum sh2000_inject what,
		     unsigned int axis, unsigned int arg);
void sh2000_fw_probe(const struct sh2000_fw *fw, struct sh2000_probe *p);
/* Addition: the machine's geometry becomes *g (NULL: perfect). The
 * counters do not jump: each scale is as if re-mounted where the carriage
 * stands. -22 on a pitch period <= 0 or a travel of no length. */
int sh2000_fw_set_geometry(struct sh2000_fw *fw, const struct sh2000_geometry *g);
/* Addition: the simulated laser interferometer: where the tool truly is
 * (mm, machine frame: sh2000_geometry_tool() of the carriages), beside
 * what the scales read. Not visible to a host through the device API. */
void sh2000_fw_tool_position(const struct sh2000_fw *fw,
			     double tool_mm[SH2000_AXES]);
/* Addition: what the compensation tables add to each axis' set-point
 * this cycle (counts; 0 without tables): the loop holds the scale at the
 * nominal set-point plus this. */
void sh2000_fw_comp_offset(const struct sh2000_fw *fw,
			   double off[SH2000_AXES]);
/* Called after every servo cycle with the probe of that cycle (traces,
 * tests); NULL removes it. Runs inside sh2000_fw_cycle(): keep it short. */
typedef void (*sh2000_fw_observer)(void *ctx, const struct sh2000_probe *p);
void sh2000_fw_set_observer(struct sh2000_fw *fw, sh2000_fw_observer fn,
			    void *ctx);

/* Addition: the card's machine becomes a gantry (NULL: independent axes
 * again). Positions are kept. -22 when the configuration is not one
 * (sides equal or beyond the axes, a carriage axis that is a side, a span
 * <= 0, negative masses or stiffness). */
int sh2000_fw_set_gantry(struct sh2000_fw *fw,
			 const struct sh2000_gantry_config *g);
/* The beam's yaw as the machine has it: side a minus side b, mm (0
 * without a gantry). Tests and benchmarks; a host sees the encoders. */
double sh2000_fw_gantry_yaw_mm(const struct sh2000_fw *fw);

/* ---- a whole card in virtual time ---- */

struct sh2000_cardsim;

int sh2000_cardsim_create(struct sh2000_cardsim **out,
			  const struct sh2000_sim_config *cfg);
void sh2000_cardsim_destroy(struct sh2000_cardsim *c);
/* The FPGA's registers (SH2000_REG_*): one port cycle each. */
void sh2000_cardsim_out(struct sh2000_cardsim *c, unsigned int reg, uint16_t v);
uint16_t sh2000_cardsim_in(struct sh2000_cardsim *c, unsigned int reg);
/* Let host time pass without port cycles (a host that waits). Servo
 * cycles fall at the card's periods in host time (sh2000_fw_set_clock_ppm
 * on sh2000_cardsim_fw()). */
void sh2000_cardsim_advance(struct sh2000_cardsim *c, uint64_t ns);
/* Host time, starting at 0. */
uint64_t sh2000_cardsim_now_ns(const struct sh2000_cardsim *c);
/* The firmware inside, for injection and probing. */
struct sh2000_fw *sh2000_cardsim_fw(struct sh2000_cardsim *c);
/* Port cycles issued: clears, increments, data reads, data writes. */
void sh2000_cardsim_counters(const struct sh2000_cardsim *c, uint64_t out[4]);
/* Addition: the RAM itself (tests, traces; a host uses the registers). */
uint16_t *sh2000_cardsim_ram(struct sh2000_cardsim *c);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_CARDSIM_H */
