/* SPDX-License-Identifier: MIT */
/*
 * libsh2000-sim: the simulated card, for tests, commissioning practice and
 * development without a card (in the spirit of libgpiod's gpiosim). It is
 * a library of its own with its own version and no ABI promise to NC
 * applications: libsh2000 loads it when a program opens `sim`.
 *
 * Here: opening an in-process `sim` card with a plant configuration,
 * reaching into it (fault injection, probes, observers), and serving a card
 * model over POSIX shared memory for `sim:NAME` handles in other
 * processes. The model itself is sh2000_cardsim.h.
 *
 * Same error rule as sh2000.h. Functions taking a handle return
 * -SH2000_ENOTSIM unless it was opened on `sim`.
 */
#ifndef SH2000_SIM_H
#define SH2000_SIM_H

#include <stddef.h>
#include <stdint.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_cardsim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the libsh2000-sim that is running ("MAJOR.MINOR.PATCH"). */
const char *sh2000_sim_version(void);

/* ---- an in-process card (`sim`) ------------------------------------- */

/* Open `sim` with a plant configuration (NULL: the documented defaults). */
int sh2000_sim_open(struct sh2000 **out, const struct sh2000_sim_config *cfg,
		    char *msg, size_t msglen);
/* The card model inside the handle (NULL unless `sim`). Calls on it must
 * be serialised with the handle: use sh2000_sim_*() from threads. */
struct sh2000_cardsim *sh2000_sim_card(struct sh2000 *h);
int sh2000_sim_inject(struct sh2000 *h, enum sh2000_inject what,
		      unsigned int axis, unsigned int arg);
int sh2000_sim_probe(struct sh2000 *h, struct sh2000_probe *p);
/* Addition: the machine's geometry (sh2000_fw_set_geometry()). */
int sh2000_sim_set_geometry(struct sh2000 *h, const struct sh2000_geometry *g);
/* Addition: the simulated interferometer (sh2000_fw_tool_position()): the
 * tool's true position in mm, machine frame. */
int sh2000_sim_tool_position(struct sh2000 *h, double tool_mm[SH2000_AXES]);
/* fn runs after every servo cycle, inside the library's calls on h. */
int sh2000_sim_set_observer(struct sh2000 *h, sh2000_fw_observer fn,
			    void *ctx);
/* Addition: the card oscillator's error in ppm (sh2000_fw_set_clock_ppm):
 * in virtual time, the card's cycles per host second become
 * 1 / (period * (1 + ppm * 1e-6)). -EINVAL beyond +-100000. */
int sh2000_sim_set_clock_ppm(struct sh2000 *h, double ppm);

/* ---- serving a card for `sim:NAME` ---------------------------------- */

struct sh2000_sim_server;

/* sh2000_sim_server_create() flags */
#define SH2000_SIM_SERVER_FREE_RUN	0x0001u	/* no sleeping: cycles
						   back to back (stress) */

/*
 * Create the shared-memory object /sh2000-NAME (fails with -EEXIST if a
 * live server owns it; a stale one left by a dead owner is replaced) and
 * a card model on it. The server holds a lock on the object while it
 * lives: of servers started on one name at once exactly one wins. cfg
 * NULL: defaults. msg gets the reason on failure.
 */
int sh2000_sim_server_create(struct sh2000_sim_server **out, const char *name,
			     const struct sh2000_sim_config *cfg,
			     unsigned int flags, char *msg, size_t msglen);
/*
 * The same server on a RAM the caller has mapped and keeps owning (the
 * kernel simulated card's DSP page /dev/sh2000-dsp-N, or a file): no shared
 * memory object is created. The magic word reads 0 ("no firmware") until
 * the model runs and again after destroy.
 */
int sh2000_sim_server_attach(struct sh2000_sim_server **out, uint16_t *ram,
			     const struct sh2000_sim_config *cfg,
			     unsigned int flags, char *msg, size_t msglen);
/* Run servo cycles at the servo period in real time in the calling thread
 * until sh2000_sim_server_stop() (from another thread or a signal
 * handler: it only sets a flag). */
int sh2000_sim_server_run(struct sh2000_sim_server *s);
/* Or in a thread the server owns. */
int sh2000_sim_server_start(struct sh2000_sim_server *s);
void sh2000_sim_server_stop(struct sh2000_sim_server *s);
/* Stops (joins the thread if started), unlinks the object (or clears the
 * attached RAM's magic word), frees. */
void sh2000_sim_server_destroy(struct sh2000_sim_server *s);
/* Applied between two servo cycles. */
int sh2000_sim_server_inject(struct sh2000_sim_server *s,
			     enum sh2000_inject what, unsigned int axis,
			     unsigned int arg);
int sh2000_sim_server_probe(struct sh2000_sim_server *s,
			    struct sh2000_probe *p);
uint64_t sh2000_sim_server_cycles(struct sh2000_sim_server *s);
/* Addition: the served card's oscillator error; the server then runs one
 * cycle every period * (1 + ppm * 1e-6) of CLOCK_MONOTONIC. Applied
 * between two cycles. -EINVAL beyond +-100000. */
int sh2000_sim_server_set_clock_ppm(struct sh2000_sim_server *s, double ppm);
/* Addition: the served card's machine becomes a gantry
 * (sh2000_fw_set_gantry; NULL: independent axes again). Applied between
 * two cycles. -EINVAL when g is not a gantry the model can run. */
int sh2000_sim_server_set_gantry(struct sh2000_sim_server *s,
				 const struct sh2000_gantry_config *g);
/* Addition: the served card's machine geometry (sh2000_fw_set_geometry();
 * NULL: perfect). Applied between two cycles. -EINVAL as that call. */
int sh2000_sim_server_set_geometry(struct sh2000_sim_server *s,
				   const struct sh2000_geometry *g);
/* Addition: the served card's simulated interferometer
 * (sh2000_fw_tool_position()): the tool's true position in mm, machine
 * frame, after the last cycle. */
int sh2000_sim_server_tool_position(struct sh2000_sim_server *s,
				    double tool_mm[SH2000_AXES]);
/* The shared-memory object's name ("/sh2000-NAME"; "" when attached). */
const char *sh2000_sim_server_shm_name(const struct sh2000_sim_server *s);

#ifdef __cplusplus
}
#endif

#endif /* SH2000_SIM_H */
