// SPDX-License-Identifier: GPL-2.0
/*
 * sh2000.ko: module entry and the real-card backend.
 *
 * Each io= base becomes a platform device bound to the "sh2000" platform
 * driver. Debian's stock kernel has no ISA bus API (CONFIG_ISA_BUS=n), and a
 * platform device works with or without it. ISA space is never probed: the
 * user names the base set by the card's switches.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/device.h>
#include <linux/err.h>
#include <linux/io.h>
#include <linux/ioport.h>
#include <linux/kernel.h>
#include <linux/module.h>
#include <linux/moduleparam.h>
#include <linux/platform_device.h>

#include "sh2000_core.h"
#include "sh2000_hw.h"
#include "uapi/sh2000.h"

#define SH2000_DRV_NAME		"sh2000"

static unsigned int io[SH2000_MAX_ISA_CARDS];
static unsigned int nr_io;
module_param_hw_array(io, uint, ioport, &nr_io, 0444);
MODULE_PARM_DESC(io, "I/O base of each card (up to 4; 4-byte aligned, 0x100..0x3fc)");

static struct platform_device *sh2000_pdevs[SH2000_MAX_ISA_CARDS];

/**
 * struct sh2000_isa - a real card's claimed window
 * @base:	first of the 4 claimed ports
 * @card:	the core's card
 */
struct sh2000_isa {
	unsigned long base;
	struct sh2000_card *card;
};

/* The clear and increment registers react to a write; the value is ignored. */
static void sh2000_isa_clear(void *priv)
{
	struct sh2000_isa *isa = priv;

	outb(0, isa->base + SH2000_REG_ADDR_CLEAR);
}

static void sh2000_isa_increment(void *priv)
{
	struct sh2000_isa *isa = priv;

	outb(0, isa->base + SH2000_REG_ADDR_INC);
}

static u16 sh2000_isa_read_data(void *priv)
{
	struct sh2000_isa *isa = priv;

	return inw(isa->base + SH2000_REG_DATA);
}

static void sh2000_isa_write_data(void *priv, u16 val)
{
	struct sh2000_isa *isa = priv;

	outw(val, isa->base + SH2000_REG_DATA);
}

static const struct sh2000_port_ops sh2000_isa_ops = {
	.clear		= sh2000_isa_clear,
	.increment	= sh2000_isa_increment,
	.read_data	= sh2000_isa_read_data,
	.write_data	= sh2000_isa_write_data,
};

/*
 * Name whoever holds ports start..end, following the descent
 * __request_region() makes: through non-busy containers (PCI bus windows)
 * down to the busy resource that refused us. resource_lock is not exported
 * (neither in 6.1 nor 6.12) and request_resource_conflict() is not exported
 * either, so this reads the tree unlocked. It runs only on the failure path,
 * for a message; the legacy-port part of the tree changes only when a driver
 * owning one of those ports is bound or unbound at the same moment.
 */
static const char *sh2000_port_owner(resource_size_t start,
				     resource_size_t end)
{
	struct resource *parent = &ioport_resource;
	struct resource *r;

	for (;;) {
		for (r = READ_ONCE(parent->child); r; r = READ_ONCE(r->sibling))
			if (r->start <= end && r->end >= start)
				break;
		if (!r)
			return parent == &ioport_resource ? NULL : parent->name;
		if ((r->flags & IORESOURCE_BUSY) || !READ_ONCE(r->child))
			return r->name;
		parent = r;
	}
}

static void sh2000_isa_unregister(void *data)
{
	struct sh2000_isa *isa = data;

	sh2000_card_unregister(isa->card);
}

static int sh2000_isa_probe(struct platform_device *pdev)
{
	struct device *dev = &pdev->dev;
	const unsigned int *base = dev_get_platdata(dev);
	struct sh2000_isa *isa;
	const char *owner;

	if (!base)
		return -EINVAL;
	if (!devm_request_region(dev, *base, SH2000_IO_EXTENT, SH2000_DRV_NAME)) {
		owner = sh2000_port_owner(*base, *base + SH2000_IO_EXTENT - 1);
		dev_err(dev, "I/O ports 0x%x-0x%x already in use by %s\n",
			*base, *base + SH2000_IO_EXTENT - 1,
			owner ? owner : "an unnamed resource");
		return -EBUSY;
	}

	isa = devm_kzalloc(dev, sizeof(*isa), GFP_KERNEL);
	if (!isa)
		return -ENOMEM;
	isa->base = *base;
	isa->card = sh2000_card_register(dev, &sh2000_isa_ops, isa, *base, 0,
					 pdev->id);
	if (IS_ERR(isa->card))
		return PTR_ERR(isa->card);
	platform_set_drvdata(pdev, isa);
	/* devres runs this before it releases the region: no cycle after. */
	return devm_add_action_or_reset(dev, sh2000_isa_unregister, isa);
}

static struct platform_driver sh2000_isa_driver = {
	.probe	= sh2000_isa_probe,
	.driver	= {
		.name		= SH2000_DRV_NAME,
		.probe_type	= PROBE_FORCE_SYNCHRONOUS,
	},
};

/* Refuse the whole load on a bad io= so a typo never half-configures. */
static int __init sh2000_check_io(void)
{
	unsigned int i, j;

	for (i = 0; i < nr_io; i++) {
		if (!sh2000_io_base_valid(io[i])) {
			pr_err("io=0x%x rejected: a base must be 4-byte aligned and within 0x%x..0x%x\n",
			       io[i], SH2000_IO_MIN, SH2000_IO_MAX);
			return -EINVAL;
		}
		for (j = 0; j < i; j++) {
			if (io[j] == io[i]) {
				pr_err("io=0x%x rejected: given more than once\n",
				       io[i]);
				return -EINVAL;
			}
		}
	}
	return 0;
}

static void sh2000_remove_pdevs(void)
{
	int i;

	for (i = SH2000_MAX_ISA_CARDS - 1; i >= 0; i--) {
		platform_device_unregister(sh2000_pdevs[i]);
		sh2000_pdevs[i] = NULL;
	}
}

static int __init sh2000_init(void)
{
	struct platform_device *pdev;
	unsigned int i, up = 0;
	int ret;

	ret = sh2000_check_io();
	if (ret)
		return ret;
	ret = sh2000_core_init();
	if (ret)
		return ret;
	ret = platform_driver_register(&sh2000_isa_driver);
	if (ret)
		goto err_core;

	/* Synchronous probes: io[i] comes up as /dev/sh2000-i. */
	for (i = 0; i < nr_io; i++) {
		pdev = platform_device_register_data(NULL, SH2000_DRV_NAME, i,
						     &io[i], sizeof(io[i]));
		if (IS_ERR(pdev)) {
			ret = PTR_ERR(pdev);
			goto err_pdevs;
		}
		sh2000_pdevs[i] = pdev;
		/* The driver core clears drvdata when a probe fails. */
		if (platform_get_drvdata(pdev))
			up++;
	}
	/* A card that failed (-EBUSY) stays down; the others keep working. */
	pr_info("driver %s, ABI %d: %u of %u card(s) from io= up\n",
		SH2000_DRIVER_VERSION, SH2000_ABI_VERSION, up, nr_io);
	return 0;

err_pdevs:
	sh2000_remove_pdevs();
	platform_driver_unregister(&sh2000_isa_driver);
err_core:
	sh2000_core_exit();
	return ret;
}

static void __exit sh2000_exit(void)
{
	sh2000_remove_pdevs();
	platform_driver_unregister(&sh2000_isa_driver);
	sh2000_core_exit();
}

module_init(sh2000_init);
module_exit(sh2000_exit);

MODULE_DESCRIPTION("SH-2000TH ISA motion card: dual-port RAM as /dev/sh2000-N");
MODULE_AUTHOR("SH-2000 project");
MODULE_LICENSE("GPL");
MODULE_VERSION(SH2000_DRIVER_VERSION);
