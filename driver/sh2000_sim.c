// SPDX-License-Identifier: GPL-2.0
/*
 * sh2000_sim.ko: simulated SH-2000TH cards, in the spirit of gpio-sim.
 *
 * Each card is a 10-bit address counter and 1024 words of dual-port RAM with
 * the register semantics of docs/card.md. The host side registers with the
 * sh2000 core exactly as a real card does (only the port accessors differ),
 * so it appears as /dev/sh2000-N. The card (DSP) side is /dev/sh2000-dsp-N
 * (same N): pread/pwrite/lseek on the 2048 bytes, and mmap of one shared
 * page whose first 2048 bytes are the RAM, so a card-model process can play
 * the DSP with 16-bit atomic loads and stores.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/err.h>
#include <linux/fs.h>
#include <linux/gfp.h>
#include <linux/kernel.h>
#include <linux/mm.h>
#include <linux/module.h>
#include <linux/moduleparam.h>
#include <linux/platform_device.h>
#include <linux/slab.h>
#include <linux/uaccess.h>

#include "sh2000_core.h"
#include "sh2000_hw.h"
#include "uapi/sh2000.h"

#define SH2000_SIM_MAX_CARDS	8
#define SH2000_SIM_CHUNK_WORDS	64

static unsigned int cards = 1;
module_param(cards, uint, 0444);
MODULE_PARM_DESC(cards, "number of simulated cards (1..8, default 1)");

/**
 * struct sh2000_sim - one simulated card
 * @dsp_dev:	/dev/sh2000-dsp-N class device; its release frees the card
 * @dsp_cdev:	the DSP-side character device
 * @pdev:	platform device both sides hang off
 * @host:	the sh2000 core's card (host side)
 * @host_index:	N of /dev/sh2000-N, kept for sysfs after @host is gone
 * @page:	the page holding the RAM (mapped by the DSP side)
 * @ram:	1024 little-endian words at the start of @page
 * @counter:	the FPGA address counter (10 bits)
 *
 * @counter is driven only by the host-side port ops, which the core
 * serialises with the card mutex; the sysfs attribute may move it behind
 * the core's back, which is what a real debugger could do too.
 */
struct sh2000_sim {
	struct device dsp_dev;
	struct cdev dsp_cdev;
	struct platform_device *pdev;
	struct sh2000_card *host;
	int host_index;
	struct page *page;
	__le16 *ram;
	unsigned int counter;
};

static struct sh2000_sim *sh2000_sims[SH2000_SIM_MAX_CARDS];
static dev_t sh2000_dsp_devt;

/* Host side: the four port cycles of card.md. */

static void sh2000_sim_clear(void *priv)
{
	struct sh2000_sim *sim = priv;

	WRITE_ONCE(sim->counter, 0);
}

static void sh2000_sim_increment(void *priv)
{
	struct sh2000_sim *sim = priv;

	WRITE_ONCE(sim->counter,
		   (READ_ONCE(sim->counter) + 1) & SH2000_ADDR_MASK);
}

static u16 sh2000_sim_read_data(void *priv)
{
	struct sh2000_sim *sim = priv;
	unsigned int addr = READ_ONCE(sim->counter) & SH2000_ADDR_MASK;

	return le16_to_cpu(READ_ONCE(sim->ram[addr]));
}

static void sh2000_sim_write_data(void *priv, u16 val)
{
	struct sh2000_sim *sim = priv;
	unsigned int addr = READ_ONCE(sim->counter) & SH2000_ADDR_MASK;

	WRITE_ONCE(sim->ram[addr], cpu_to_le16(val));
}

static const struct sh2000_port_ops sh2000_sim_ops = {
	.clear		= sh2000_sim_clear,
	.increment	= sh2000_sim_increment,
	.read_data	= sh2000_sim_read_data,
	.write_data	= sh2000_sim_write_data,
};

/*
 * DSP side: the RAM as the card sees it, with no address counter and no
 * port cycles counted. The same offset rules as /dev/sh2000-N apply, so
 * every word moves as one 16-bit access and is never torn.
 */

static ssize_t sh2000_dsp_read(struct file *file, char __user *buf,
			       size_t count, loff_t *ppos)
{
	struct sh2000_sim *sim = file->private_data;
	__le16 bounce[SH2000_SIM_CHUNK_WORDS];
	unsigned int word, done = 0, n, i, k;
	ssize_t ret;

	ret = sh2000_ram_span(*ppos, count);
	if (ret <= 0)
		return ret;
	n = ret;
	word = *ppos / 2;
	while (done < n) {
		k = min_t(unsigned int, n - done, SH2000_SIM_CHUNK_WORDS);
		for (i = 0; i < k; i++)
			bounce[i] = READ_ONCE(sim->ram[word + done + i]);
		if (copy_to_user(buf + 2 * done, bounce, 2 * k))
			break;
		done += k;
	}
	if (!done)
		return -EFAULT;
	*ppos += 2 * done;
	return 2 * done;
}

static ssize_t sh2000_dsp_write(struct file *file, const char __user *buf,
				size_t count, loff_t *ppos)
{
	struct sh2000_sim *sim = file->private_data;
	__le16 bounce[SH2000_SIM_CHUNK_WORDS];
	unsigned int word, done = 0, n, i, k;
	ssize_t ret;

	ret = sh2000_ram_span(*ppos, count);
	if (ret < 0)
		return ret;
	if (ret == 0)
		return count ? -ENOSPC : 0;
	n = ret;
	word = *ppos / 2;
	while (done < n) {
		k = min_t(unsigned int, n - done, SH2000_SIM_CHUNK_WORDS);
		if (copy_from_user(bounce, buf + 2 * done, 2 * k))
			break;
		for (i = 0; i < k; i++)
			WRITE_ONCE(sim->ram[word + done + i], bounce[i]);
		done += k;
	}
	if (!done)
		return -EFAULT;
	*ppos += 2 * done;
	return 2 * done;
}

/* One shared page at offset 0; the RAM is its first 2048 bytes. */
static int sh2000_dsp_mmap(struct file *file, struct vm_area_struct *vma)
{
	struct sh2000_sim *sim = file->private_data;

	if (vma->vm_pgoff || vma->vm_end - vma->vm_start != PAGE_SIZE)
		return -EINVAL;
	if (!(vma->vm_flags & VM_SHARED))
		return -EINVAL;
	return vm_insert_page(vma, vma->vm_start, sim->page);
}

static int sh2000_dsp_open(struct inode *inode, struct file *file)
{
	file->private_data = container_of(inode->i_cdev, struct sh2000_sim,
					  dsp_cdev);
	return 0;
}

/* The owner pins this module, so the card outlives every file and mapping. */
static const struct file_operations sh2000_dsp_fops = {
	.owner		= THIS_MODULE,
	.open		= sh2000_dsp_open,
	.read		= sh2000_dsp_read,
	.write		= sh2000_dsp_write,
	.llseek		= sh2000_ram_llseek,
	.mmap		= sh2000_dsp_mmap,
};

/* /sys/class/sh2000_dsp/sh2000-dsp-N/{host,counter} */

static struct sh2000_sim *to_sim(struct device *dev)
{
	return container_of(dev, struct sh2000_sim, dsp_dev);
}

static ssize_t host_show(struct device *dev, struct device_attribute *attr,
			 char *buf)
{
	return sysfs_emit(buf, "sh2000-%d\n", to_sim(dev)->host_index);
}
static DEVICE_ATTR_RO(host);

static ssize_t counter_show(struct device *dev, struct device_attribute *attr,
			    char *buf)
{
	return sysfs_emit(buf, "%u\n", READ_ONCE(to_sim(dev)->counter));
}

/* Moves the counter behind the driver's back (tests FORGET_POSITION). */
static ssize_t counter_store(struct device *dev, struct device_attribute *attr,
			     const char *buf, size_t count)
{
	unsigned int val;
	int ret;

	ret = kstrtouint(buf, 0, &val);
	if (ret)
		return ret;
	if (val >= SH2000_RAM_WORDS)
		return -EINVAL;
	WRITE_ONCE(to_sim(dev)->counter, val);
	return count;
}
static DEVICE_ATTR_RW(counter);

static struct attribute *sh2000_dsp_attrs[] = {
	&dev_attr_host.attr,
	&dev_attr_counter.attr,
	NULL,
};
ATTRIBUTE_GROUPS(sh2000_dsp);

static struct class sh2000_dsp_class = {
	.name		= "sh2000_dsp",
	.dev_groups	= sh2000_dsp_groups,
};

static void sh2000_dsp_release(struct device *dev)
{
	struct sh2000_sim *sim = to_sim(dev);

	if (sim->page)
		__free_page(sim->page);
	kfree(sim);
}

static struct sh2000_sim *sh2000_sim_create(unsigned int id)
{
	struct sh2000_sim *sim;
	int ret;

	sim = kzalloc(sizeof(*sim), GFP_KERNEL);
	if (!sim)
		return ERR_PTR(-ENOMEM);
	device_initialize(&sim->dsp_dev);
	sim->dsp_dev.class = &sh2000_dsp_class;
	sim->dsp_dev.release = sh2000_dsp_release;

	sim->page = alloc_page(GFP_KERNEL | __GFP_ZERO);
	if (!sim->page) {
		ret = -ENOMEM;
		goto err_put;
	}
	sim->ram = page_address(sim->page);

	sim->pdev = platform_device_register_simple("sh2000_sim", id, NULL, 0);
	if (IS_ERR(sim->pdev)) {
		ret = PTR_ERR(sim->pdev);
		sim->pdev = NULL;
		goto err_put;
	}

	sim->host = sh2000_card_register(&sim->pdev->dev, &sh2000_sim_ops, sim,
					 0, SH2000_INFO_SIMULATED, -1);
	if (IS_ERR(sim->host)) {
		ret = PTR_ERR(sim->host);
		goto err_pdev;
	}
	sim->host_index = sh2000_card_index(sim->host);

	sim->dsp_dev.parent = &sim->pdev->dev;
	sim->dsp_dev.devt = MKDEV(MAJOR(sh2000_dsp_devt), id);
	ret = dev_set_name(&sim->dsp_dev, "sh2000-dsp-%d", sim->host_index);
	if (ret)
		goto err_host;
	cdev_init(&sim->dsp_cdev, &sh2000_dsp_fops);
	sim->dsp_cdev.owner = THIS_MODULE;
	ret = cdev_device_add(&sim->dsp_cdev, &sim->dsp_dev);
	if (ret)
		goto err_host;
	return sim;

err_host:
	sh2000_card_unregister(sim->host);
err_pdev:
	platform_device_unregister(sim->pdev);
err_put:
	put_device(&sim->dsp_dev);
	return ERR_PTR(ret);
}

/*
 * The host side goes first: after sh2000_card_unregister() the core never
 * calls our port ops again, even for a /dev/sh2000-N that stays open.
 */
static void sh2000_sim_destroy(struct sh2000_sim *sim)
{
	struct platform_device *pdev = sim->pdev;

	sh2000_card_unregister(sim->host);
	cdev_device_del(&sim->dsp_cdev, &sim->dsp_dev);
	put_device(&sim->dsp_dev);
	platform_device_unregister(pdev);
}

static void sh2000_sim_destroy_all(void)
{
	int i;

	for (i = SH2000_SIM_MAX_CARDS - 1; i >= 0; i--) {
		if (sh2000_sims[i])
			sh2000_sim_destroy(sh2000_sims[i]);
		sh2000_sims[i] = NULL;
	}
}

static int __init sh2000_sim_init(void)
{
	struct sh2000_sim *sim;
	unsigned int i;
	int ret;

	if (cards < 1 || cards > SH2000_SIM_MAX_CARDS) {
		pr_err("cards=%u rejected: must be 1..%u\n", cards,
		       SH2000_SIM_MAX_CARDS);
		return -EINVAL;
	}
	ret = alloc_chrdev_region(&sh2000_dsp_devt, 0, SH2000_SIM_MAX_CARDS,
				  "sh2000_dsp");
	if (ret)
		return ret;
	ret = class_register(&sh2000_dsp_class);
	if (ret)
		goto err_region;

	for (i = 0; i < cards; i++) {
		sim = sh2000_sim_create(i);
		if (IS_ERR(sim)) {
			ret = PTR_ERR(sim);
			pr_err("simulated card %u: error %d\n", i, ret);
			goto err_cards;
		}
		sh2000_sims[i] = sim;
	}
	pr_info("%u simulated card(s)\n", cards);
	return 0;

err_cards:
	sh2000_sim_destroy_all();
	class_unregister(&sh2000_dsp_class);
err_region:
	unregister_chrdev_region(sh2000_dsp_devt, SH2000_SIM_MAX_CARDS);
	return ret;
}

static void __exit sh2000_sim_exit(void)
{
	sh2000_sim_destroy_all();
	class_unregister(&sh2000_dsp_class);
	unregister_chrdev_region(sh2000_dsp_devt, SH2000_SIM_MAX_CARDS);
}

module_init(sh2000_sim_init);
module_exit(sh2000_sim_exit);

MODULE_DESCRIPTION("SH-2000TH simulated cards for the sh2000 driver");
MODULE_AUTHOR("SH-2000 project");
MODULE_LICENSE("GPL");
MODULE_VERSION(SH2000_DRIVER_VERSION);
