// SPDX-License-Identifier: GPL-2.0
/*
 * sh2000 core: one character device per SH-2000TH card, /dev/sh2000-N,
 * presenting the card's 2 KiB dual-port RAM as a seekable file.
 *
 * The host reaches the RAM only through an address counter that can be
 * cleared or incremented, so the core remembers where the counter is and
 * moves it with sh2000_seek_plan(), the seek logic libsh2000 shares.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/cdev.h>
#include <linux/compat.h>
#include <linux/device.h>
#include <linux/fs.h>
#include <linux/idr.h>
#include <linux/kernel.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/sched.h>
#include <linux/sched/signal.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "sh2000_core.h"
#include "sh2000_hw.h"
#include "sh2000_seek.h"
#include "uapi/sh2000.h"

/*
 * Words moved per bounce-buffer chunk: copy_{to,from}_user never runs inside
 * a port loop, and between chunks the task may be rescheduled or stop for a
 * signal. 64 words are about 128 port cycles (~128 us on a real ISA bus).
 */
#define SH2000_CHUNK_WORDS	64

/* The ABI promises one layout for 32-bit and 64-bit callers. */
static_assert(sizeof(struct sh2000_info) == 72);
static_assert(sizeof(struct sh2000_counters) == 40);
static_assert(SH2000_POSITION_UNKNOWN == SH2000_SEEK_UNKNOWN);

/**
 * struct sh2000_card - one card, real or simulated
 * @dev:	the class device; its release frees the card
 * @cdev:	/dev/sh2000-N; an open file holds a reference on @dev
 * @lock:	serialises every port cycle, @pos, the counters and @dead
 * @dead:	set by sh2000_card_unregister(): @ops may be gone
 * @ops:	port accessors of the backend
 * @priv:	backend cookie passed to @ops
 * @base:	I/O base (0 for a simulated card)
 * @flags:	SH2000_INFO_* bits
 * @index:	N of /dev/sh2000-N
 * @pos:	address counter position, or SH2000_SEEK_UNKNOWN
 * @clears:	address-clear cycles issued
 * @increments:	address-increment cycles issued
 * @data_reads:	data-register reads issued
 * @data_writes: data-register writes issued
 * @bounce:	staging area between user memory and the port loop
 */
struct sh2000_card {
	struct device dev;
	struct cdev cdev;
	struct mutex lock;	/* port cycles, @pos, counters, @dead */
	bool dead;
	const struct sh2000_port_ops *ops;
	void *priv;
	unsigned int base;
	u32 flags;
	int index;
	unsigned int pos;
	u64 clears;
	u64 increments;
	u64 data_reads;
	u64 data_writes;
	u16 bounce[SH2000_CHUNK_WORDS];
};

static dev_t sh2000_devt;
static DEFINE_IDA(sh2000_ida);

static struct sh2000_card *to_card(struct device *dev)
{
	return container_of(dev, struct sh2000_card, dev);
}

/* Move the address counter to @target the cheapest way. Lock held. */
static void sh2000_seek_to(struct sh2000_card *card, unsigned int target)
{
	struct sh2000_seek plan;
	unsigned int i;

	if (card->pos == target)
		return;
	plan = sh2000_seek_plan(card->pos, target);
	if (plan.clear) {
		card->ops->clear(card->priv);
		card->clears++;
	}
	for (i = 0; i < plan.increments; i++)
		card->ops->increment(card->priv);
	card->increments += plan.increments;
	card->pos = target;
}

/**
 * sh2000_ram_span() - the file rules of the 2048-byte RAM, for read and write
 * @pos:	file position
 * @count:	bytes asked for
 *
 * Shared by the host side (/dev/sh2000-N) and the simulated card's DSP side
 * (/dev/sh2000-dsp-N), which follow the same rules.
 *
 * Return: the number of words to move (0 at or past the end), or -EINVAL
 * for an odd position or length.
 */
ssize_t sh2000_ram_span(loff_t pos, size_t count)
{
	if ((pos | count) & 1)
		return -EINVAL;
	if (pos >= SH2000_RAM_BYTES)
		return 0;
	return min_t(size_t, count, SH2000_RAM_BYTES - pos) / 2;
}
EXPORT_SYMBOL_GPL(sh2000_ram_span);

/**
 * sh2000_ram_llseek() - the new file position of an lseek on the RAM
 * @file:	the file, whose f_pos is updated
 * @offset:	as passed to lseek
 * @whence:	SEEK_SET, SEEK_CUR or SEEK_END (anything else is -EINVAL)
 *
 * The position stays within 0..2048; an odd one is accepted here and
 * refused by the next transfer.
 *
 * Return: the new position or -EINVAL.
 */
loff_t sh2000_ram_llseek(struct file *file, loff_t offset, int whence)
{
	loff_t base, pos;

	switch (whence) {
	case SEEK_SET:
		base = 0;
		break;
	case SEEK_CUR:
		base = file->f_pos;
		break;
	case SEEK_END:
		base = SH2000_RAM_BYTES;
		break;
	default:
		return -EINVAL;
	}
	if (check_add_overflow(base, offset, &pos) || pos < 0 ||
	    pos > SH2000_RAM_BYTES)
		return -EINVAL;
	file->f_pos = pos;
	return pos;
}
EXPORT_SYMBOL_GPL(sh2000_ram_llseek);

static int sh2000_lock_live(struct sh2000_card *card)
{
	if (mutex_lock_interruptible(&card->lock))
		return -ERESTARTSYS;
	if (card->dead) {
		mutex_unlock(&card->lock);
		return -ENODEV;
	}
	return 0;
}

static ssize_t sh2000_read(struct file *file, char __user *buf, size_t count,
			   loff_t *ppos)
{
	struct sh2000_card *card = file->private_data;
	unsigned int word, done = 0, n, i, k;
	ssize_t ret;

	ret = sh2000_lock_live(card);
	if (ret)
		return ret;
	ret = sh2000_ram_span(*ppos, count);
	if (ret <= 0)
		goto out;
	n = ret;
	word = *ppos / 2;
	ret = 0;
	while (done < n) {
		if (signal_pending(current)) {
			ret = -ERESTARTSYS;
			break;
		}
		k = min_t(unsigned int, n - done, SH2000_CHUNK_WORDS);
		for (i = 0; i < k; i++) {
			sh2000_seek_to(card, word + done + i);
			card->bounce[i] = card->ops->read_data(card->priv);
		}
		card->data_reads += k;
		for (i = 0; i < k; i++)
			cpu_to_le16s(&card->bounce[i]);
		if (copy_to_user(buf + 2 * done, card->bounce, 2 * k)) {
			ret = -EFAULT;
			break;
		}
		done += k;
		cond_resched();
	}
	if (done) {
		*ppos += 2 * done;
		ret = 2 * done;
	}
out:
	mutex_unlock(&card->lock);
	return ret;
}

static ssize_t sh2000_write(struct file *file, const char __user *buf,
			    size_t count, loff_t *ppos)
{
	struct sh2000_card *card = file->private_data;
	unsigned int word, done = 0, n, i, k;
	ssize_t ret;

	ret = sh2000_lock_live(card);
	if (ret)
		return ret;
	ret = sh2000_ram_span(*ppos, count);
	if (ret < 0)
		goto out;
	if (ret == 0) {
		if (count)
			ret = -ENOSPC;
		goto out;
	}
	n = ret;
	word = *ppos / 2;
	ret = 0;
	while (done < n) {
		if (signal_pending(current)) {
			ret = -ERESTARTSYS;
			break;
		}
		k = min_t(unsigned int, n - done, SH2000_CHUNK_WORDS);
		if (copy_from_user(card->bounce, buf + 2 * done, 2 * k)) {
			ret = -EFAULT;
			break;
		}
		for (i = 0; i < k; i++)
			le16_to_cpus(&card->bounce[i]);
		for (i = 0; i < k; i++) {
			sh2000_seek_to(card, word + done + i);
			card->ops->write_data(card->priv, card->bounce[i]);
		}
		card->data_writes += k;
		done += k;
		cond_resched();
	}
	if (done) {
		*ppos += 2 * done;
		ret = 2 * done;
	}
out:
	mutex_unlock(&card->lock);
	return ret;
}

/* SEEK_SET, SEEK_CUR and SEEK_END within 0..2048; odd offsets fail later. */
static loff_t sh2000_llseek(struct file *file, loff_t offset, int whence)
{
	struct sh2000_card *card = file->private_data;

	if (whence != SEEK_SET && whence != SEEK_CUR && whence != SEEK_END)
		return -EINVAL;
	if (READ_ONCE(card->dead))
		return -ENODEV;
	return sh2000_ram_llseek(file, offset, whence);
}

static long sh2000_get_info(struct sh2000_card *card, void __user *argp)
{
	struct sh2000_info info;

	/* Fixed at registration: no lock needed to read it. */
	memset(&info, 0, sizeof(info));
	info.abi_version = SH2000_ABI_VERSION;
	info.base = card->base;
	info.ram_bytes = SH2000_RAM_BYTES;
	info.ram_words = SH2000_RAM_WORDS;
	info.index = card->index;
	info.flags = card->flags;
	strscpy(info.driver_version, SH2000_DRIVER_VERSION,
		sizeof(info.driver_version));
	if (copy_to_user(argp, &info, sizeof(info)))
		return -EFAULT;
	return 0;
}

static long sh2000_get_counters(struct sh2000_card *card, void __user *argp)
{
	struct sh2000_counters counters;
	int ret;

	memset(&counters, 0, sizeof(counters));
	ret = sh2000_lock_live(card);
	if (ret)
		return ret;
	counters.clears = card->clears;
	counters.increments = card->increments;
	counters.data_reads = card->data_reads;
	counters.data_writes = card->data_writes;
	counters.position = card->pos;
	mutex_unlock(&card->lock);

	/* Copied out after unlocking: a fault must not stall other users. */
	if (copy_to_user(argp, &counters, sizeof(counters)))
		return -EFAULT;
	return 0;
}

static long sh2000_forget_position(struct sh2000_card *card)
{
	int ret;

	ret = sh2000_lock_live(card);
	if (ret)
		return ret;
	card->pos = SH2000_SEEK_UNKNOWN;
	mutex_unlock(&card->lock);
	return 0;
}

static long sh2000_ioctl(struct file *file, unsigned int cmd,
			 unsigned long arg)
{
	struct sh2000_card *card = file->private_data;
	void __user *argp = (void __user *)arg;

	switch (cmd) {
	case SH2000_IOC_GET_INFO:
		if (READ_ONCE(card->dead))
			return -ENODEV;
		return sh2000_get_info(card, argp);
	case SH2000_IOC_GET_COUNTERS:
		return sh2000_get_counters(card, argp);
	case SH2000_IOC_FORGET_POSITION:
		return sh2000_forget_position(card);
	default:
		return -ENOTTY;
	}
}

static int sh2000_open(struct inode *inode, struct file *file)
{
	struct sh2000_card *card = container_of(inode->i_cdev,
						struct sh2000_card, cdev);

	if (READ_ONCE(card->dead))
		return -ENODEV;
	file->private_data = card;
	return 0;
}

/*
 * No release: the open file pins the cdev, and the cdev pins the class
 * device (cdev_device_add() made it the cdev's parent), so the card
 * outlives every file. The owner pins sh2000.ko; a backend module such as
 * sh2000_sim may go away, which is why every file op checks @dead.
 */
static const struct file_operations sh2000_fops = {
	.owner		= THIS_MODULE,
	.open		= sh2000_open,
	.read		= sh2000_read,
	.write		= sh2000_write,
	.llseek		= sh2000_llseek,
	.unlocked_ioctl	= sh2000_ioctl,
	.compat_ioctl	= compat_ptr_ioctl,
};

/* sysfs: /sys/class/sh2000/sh2000-N/{base,simulated,position,counters} */

static ssize_t base_show(struct device *dev, struct device_attribute *attr,
			 char *buf)
{
	return sysfs_emit(buf, "0x%x\n", to_card(dev)->base);
}
static DEVICE_ATTR_RO(base);

static ssize_t simulated_show(struct device *dev,
			      struct device_attribute *attr, char *buf)
{
	return sysfs_emit(buf, "%d\n",
			  !!(to_card(dev)->flags & SH2000_INFO_SIMULATED));
}
static DEVICE_ATTR_RO(simulated);

static ssize_t position_show(struct device *dev,
			     struct device_attribute *attr, char *buf)
{
	struct sh2000_card *card = to_card(dev);
	unsigned int pos;

	if (mutex_lock_interruptible(&card->lock))
		return -ERESTARTSYS;
	pos = card->pos;
	mutex_unlock(&card->lock);
	if (pos == SH2000_SEEK_UNKNOWN)
		return sysfs_emit(buf, "unknown\n");
	return sysfs_emit(buf, "%u\n", pos);
}
static DEVICE_ATTR_RO(position);

static ssize_t sh2000_counter_show(struct device *dev, char *buf,
				   const u64 *counter)
{
	struct sh2000_card *card = to_card(dev);
	u64 val;

	if (mutex_lock_interruptible(&card->lock))
		return -ERESTARTSYS;
	val = *counter;
	mutex_unlock(&card->lock);
	return sysfs_emit(buf, "%llu\n", val);
}

static ssize_t clears_show(struct device *dev, struct device_attribute *attr,
			   char *buf)
{
	return sh2000_counter_show(dev, buf, &to_card(dev)->clears);
}
static DEVICE_ATTR_RO(clears);

static ssize_t increments_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	return sh2000_counter_show(dev, buf, &to_card(dev)->increments);
}
static DEVICE_ATTR_RO(increments);

static ssize_t data_reads_show(struct device *dev,
			       struct device_attribute *attr, char *buf)
{
	return sh2000_counter_show(dev, buf, &to_card(dev)->data_reads);
}
static DEVICE_ATTR_RO(data_reads);

static ssize_t data_writes_show(struct device *dev,
				struct device_attribute *attr, char *buf)
{
	return sh2000_counter_show(dev, buf, &to_card(dev)->data_writes);
}
static DEVICE_ATTR_RO(data_writes);

static struct attribute *sh2000_attrs[] = {
	&dev_attr_base.attr,
	&dev_attr_simulated.attr,
	&dev_attr_position.attr,
	&dev_attr_clears.attr,
	&dev_attr_increments.attr,
	&dev_attr_data_reads.attr,
	&dev_attr_data_writes.attr,
	NULL,
};
ATTRIBUTE_GROUPS(sh2000);

static struct class sh2000_class = {
	.name		= "sh2000",
	.dev_groups	= sh2000_groups,
};

static void sh2000_card_release(struct device *dev)
{
	kfree(to_card(dev));
}

/**
 * sh2000_card_register() - bring up /dev/sh2000-N for a card
 * @parent:	the device the card hangs off (platform device)
 * @ops:	port accessors; must stay valid until sh2000_card_unregister()
 * @priv:	cookie for @ops
 * @base:	I/O base for GET_INFO and sysfs (0 for a simulated card)
 * @flags:	SH2000_INFO_* bits
 * @index:	wanted N, or -1 for the lowest free one; a taken N falls back
 *		to the lowest free one
 *
 * Return: the card, or an ERR_PTR().
 */
struct sh2000_card *sh2000_card_register(struct device *parent,
					 const struct sh2000_port_ops *ops,
					 void *priv, unsigned int base,
					 u32 flags, int index)
{
	struct sh2000_card *card;
	int ret = -ENOSPC;

	card = kzalloc(sizeof(*card), GFP_KERNEL);
	if (!card)
		return ERR_PTR(-ENOMEM);

	if (index >= 0 && index < SH2000_MAX_CARDS)
		ret = ida_alloc_range(&sh2000_ida, index, index, GFP_KERNEL);
	if (ret < 0)
		ret = ida_alloc_max(&sh2000_ida, SH2000_MAX_CARDS - 1,
				    GFP_KERNEL);
	if (ret < 0) {
		kfree(card);
		return ERR_PTR(ret);
	}

	mutex_init(&card->lock);
	card->ops = ops;
	card->priv = priv;
	card->base = base;
	card->flags = flags;
	card->index = ret;
	card->pos = SH2000_SEEK_UNKNOWN;

	device_initialize(&card->dev);
	card->dev.class = &sh2000_class;
	card->dev.parent = parent;
	card->dev.devt = MKDEV(MAJOR(sh2000_devt), card->index);
	card->dev.release = sh2000_card_release;
	ret = dev_set_name(&card->dev, "sh2000-%d", card->index);
	if (ret)
		goto err_put;

	cdev_init(&card->cdev, &sh2000_fops);
	card->cdev.owner = THIS_MODULE;
	ret = cdev_device_add(&card->cdev, &card->dev);
	if (ret)
		goto err_put;

	if (flags & SH2000_INFO_SIMULATED)
		dev_info(parent, "%s: simulated card\n", dev_name(&card->dev));
	else
		dev_info(parent, "%s: card at I/O 0x%x\n",
			 dev_name(&card->dev), base);
	return card;

err_put:
	ida_free(&sh2000_ida, card->index);
	put_device(&card->dev);
	return ERR_PTR(ret);
}
EXPORT_SYMBOL_GPL(sh2000_card_register);

/**
 * sh2000_card_unregister() - take a card away
 * @card:	from sh2000_card_register()
 *
 * Waits for a transfer in progress, then no port op is called again. Files
 * still open get -ENODEV; the card's memory goes with the last of them.
 */
void sh2000_card_unregister(struct sh2000_card *card)
{
	mutex_lock(&card->lock);
	WRITE_ONCE(card->dead, true);
	mutex_unlock(&card->lock);

	cdev_device_del(&card->cdev, &card->dev);
	ida_free(&sh2000_ida, card->index);
	put_device(&card->dev);
}
EXPORT_SYMBOL_GPL(sh2000_card_unregister);

/* N of /dev/sh2000-N, so a backend can name its own nodes after it. */
int sh2000_card_index(const struct sh2000_card *card)
{
	return card->index;
}
EXPORT_SYMBOL_GPL(sh2000_card_index);

int sh2000_core_init(void)
{
	int ret;

	ret = alloc_chrdev_region(&sh2000_devt, 0, SH2000_MAX_CARDS, "sh2000");
	if (ret)
		return ret;
	ret = class_register(&sh2000_class);
	if (ret)
		unregister_chrdev_region(sh2000_devt, SH2000_MAX_CARDS);
	return ret;
}

void sh2000_core_exit(void)
{
	class_unregister(&sh2000_class);
	unregister_chrdev_region(sh2000_devt, SH2000_MAX_CARDS);
	ida_destroy(&sh2000_ida);
}
