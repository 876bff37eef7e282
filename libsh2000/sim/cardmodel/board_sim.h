/* SPDX-License-Identifier: MIT */
/*
 * The board from the simulation's side: building it, letting the machine
 * run between two servo interrupts, its oscillator, the faults injected
 * into the hardware, and a look at the plant for probes and tests. The
 * firmware does not include this header (board.h is its view).
 */
#ifndef SH2000_BOARD_SIM_H
#define SH2000_BOARD_SIM_H

#include <stdint.h>

#include "board.h"
#include "plant.h"
#include "sh2000_fpga.h"

/* ram: SH2000_RAM_WORDS the board uses as its dual-port RAM (not owned). */
int sh2000_board_create(struct sh2000_board **out, uint16_t *ram,
			const struct sh2000_sim_config *cfg);
void sh2000_board_destroy(struct sh2000_board *b);

/*
 * The time from one servo interrupt to the next: `card_ns` of the card's
 * clock. The plants integrate it with the DAC outputs held and the index
 * latches see the marks crossed. Returns its length in host time (the
 * oscillator's error applied, fractions of a ns carried to the next).
 */
uint64_t sh2000_board_run(struct sh2000_board *b, uint64_t card_ns);

/* The card's oscillator: a period of the card's clock lasts
 * (1 + ppm * 1e-6) of its nominal length in host time. |ppm| <= 100000. */
int sh2000_board_set_clock_ppm(struct sh2000_board *b, double ppm);
double sh2000_board_clock_ppm(const struct sh2000_board *b);
#define SH2000_BOARD_PPM_MAX	100000.0

/* The FPGA's host side (address counter, port-cycle counters) on this
 * board's RAM, for a host in the same process (cardsim.c). */
struct sh2000_fpga *sh2000_board_host(struct sh2000_board *b);
uint16_t *sh2000_board_ram(struct sh2000_board *b);

/* ---- faults in the hardware (inject.c); -22 on a bad axis or word ---- */

/* The carriage does not move (on != 0) or moves again. */
int sh2000_board_jam(struct sh2000_board *b, unsigned int axis, int on);
/* A limit switch input reads active: bit0 the - switch, bit1 the +. */
int sh2000_board_force_limit(struct sh2000_board *b, unsigned int axis,
			     unsigned int bits);
/* The encoder counter jumps by `counts` (lost or extra scale pulses). */
int sh2000_board_glitch(struct sh2000_board *b, unsigned int axis,
			int32_t counts);
/* XOR `mask` into RAM word w, once. */
int sh2000_board_flip(struct sh2000_board *b, unsigned int w, uint16_t mask);
/* The DSP's writes to RAM word w are lost until the faults are cleared. */
int sh2000_board_stick(struct sh2000_board *b, unsigned int w);
/* The host's write of its next record (number HEAD) does not reach the
 * RAM: its ring slot keeps what it held. */
void sh2000_board_drop_record(struct sh2000_board *b);
/* Undo jam, forced limits, stuck word and a pending drop. */
void sh2000_board_clear_faults(struct sh2000_board *b);

/* The machine becomes a gantry (gantry.c; NULL: axes alone again); -22
 * when g is not one. The beam's yaw, side a - side b in mm (0 without). */
int sh2000_board_set_gantry(struct sh2000_board *b,
			    const struct sh2000_gantry_config *g);
double sh2000_board_gantry_yaw_mm(const struct sh2000_board *b);

/* The machine itself (probes, tests). */
const struct sh2000_plant *sh2000_board_plant(const struct sh2000_board *b,
					      unsigned int axis);
/* The machine's geometry (NULL: perfect); the counters do not jump. */
int sh2000_board_set_geometry(struct sh2000_board *b,
			       const struct sh2000_geometry *g);
/* Where the tool is (mm, machine frame): the interferometer. */
void sh2000_board_tool(const struct sh2000_board *b, double tool[SH2000_AXES]);

#endif /* SH2000_BOARD_SIM_H */
