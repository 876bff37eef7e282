/* SPDX-License-Identifier: GPL-2.0 */
/*
 * Inside the kernel: the seam between the sh2000 core (character device,
 * address-counter tracking, ioctls, sysfs) and whatever issues the port
 * cycles. Real ISA cards (sh2000_isa.c) and simulated cards (sh2000_sim.c)
 * register through the same two functions and differ only in their
 * struct sh2000_port_ops.
 */
#ifndef SH2000_CORE_H
#define SH2000_CORE_H

#include <linux/types.h>

#define SH2000_DRIVER_VERSION	"0.1.0"

/* Real cards (io=) plus simulated cards share this many minors. */
#define SH2000_MAX_ISA_CARDS	4
#define SH2000_MAX_CARDS	16

struct device;
struct file;
struct sh2000_card;

/**
 * struct sh2000_port_ops - the four port cycles the card understands
 * @clear:	write the address-clear register (counter = 0)
 * @increment:	write the address-increment register (counter += 1, 10 bits)
 * @read_data:	16-bit read of the data register (RAM[counter])
 * @write_data:	16-bit write of the data register (RAM[counter] = @val)
 *
 * The core calls these with the card's mutex held, never with a spinlock
 * held, and never again once sh2000_card_unregister() has returned.
 */
struct sh2000_port_ops {
	void (*clear)(void *priv);
	void (*increment)(void *priv);
	u16 (*read_data)(void *priv);
	void (*write_data)(void *priv, u16 val);
};

struct sh2000_card *sh2000_card_register(struct device *parent,
					 const struct sh2000_port_ops *ops,
					 void *priv, unsigned int base,
					 u32 flags, int index);
void sh2000_card_unregister(struct sh2000_card *card);
int sh2000_card_index(const struct sh2000_card *card);

/* The RAM's file rules, shared by the host and the simulated DSP side. */
ssize_t sh2000_ram_span(loff_t pos, size_t count);
loff_t sh2000_ram_llseek(struct file *file, loff_t offset, int whence);

/* Set up and tear down the class and the minors (sh2000.ko init/exit). */
int sh2000_core_init(void);
void sh2000_core_exit(void);

#endif /* SH2000_CORE_H */
