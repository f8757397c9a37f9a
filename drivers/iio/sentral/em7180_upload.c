// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: the firmware upload from the host
 *
 * The chip runs its firmware from RAM. At power-on and after every reset
 * its ROM loads it from an EEPROM on the sensor bus; a board without one
 * (SentralStatus NoEEPROM) waits for the host to upload it, as EM's generic
 * host driver (em718x_core.c) and Sony's em718x driver do: a .fw image,
 * requested from userspace (no image is redistributable), whose 16-byte
 * little-endian header gives a magic, flags with the ROM the image was
 * built for, the CRC of the text and the text's length. The text goes to
 * UploadData in chunks of at most 64 bytes, every 32-bit word most
 * significant byte first (the image is little-endian); then CRCHost, which
 * the chip computes over what it received, must equal the header's CRC.
 * The image is kept for the uploads after a reset, which loses the RAM.
 */

#include <linux/array_size.h>
#include <linux/bitfield.h>
#include <linux/bits.h>
#include <linux/build_bug.h>
#include <linux/cleanup.h>
#include <linux/device.h>
#include <linux/errno.h>
#include <linux/firmware.h>
#include <linux/lockdep.h>
#include <linux/minmax.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/property.h>
#include <linux/regmap.h>
#include <linux/slab.h>
#include <linux/types.h>

#include <kunit/visibility.h>

#include "em7180_compat.h"
#include "em7180_core.h"

#define EM7180_FW_DEFAULT_NAME		"em7180.fw"
#define EM7180_FW_MAGIC			0x652a
#define EM7180_FW_HEADER_LEN		16
/* flags: no_exec (bit 0), I2C clock (bits 10:8), expected ROM (bits 14:11) */
#define EM7180_FW_FLAGS_ROM_MASK	GENMASK(14, 11)
#define EM7180_FW_ROM_ANY		0
#define EM7180_FW_ROM_DI01		1
#define EM7180_FW_ROM_DI02		2
/* ROMVersion of each ROM (em718x_eeprom.h) */
#define EM7180_ROM_VERSION_DI01		0x07a8
#define EM7180_ROM_VERSION_DI02		0x09e6
/* em718x_core.c writes 64 bytes at a time */
#define EM7180_UPLOAD_CHUNK		64U

MODULE_FIRMWARE(EM7180_FW_DEFAULT_NAME);

struct em7180_fw_header {
	__le16 magic;
	__le16 flags;
	__le32 text_crc;
	__le32 reserved1;
	__le16 text_length;
	__le16 reserved2;
} __packed;

static_assert(sizeof(struct em7180_fw_header) == EM7180_FW_HEADER_LEN);

/**
 * em7180_fw_check() - check a .fw image before it is uploaded
 * @image: the file's content
 * @size: its size in bytes
 * @rom: ROMVersion read from the chip
 * @why: filled with what failed, for the log
 * @len: size of @why
 *
 * The magic, a text of whole 32-bit words that the file holds entirely
 * (bytes after it are not sent, as em718x_core.c does), and the ROM the
 * image was built for against the chip's. The text's CRC is the chip's to
 * compute: no public source says which CRC it is.
 *
 * Return: 0, or -EINVAL with @why set.
 */
int em7180_fw_check(const u8 *image, size_t size, u16 rom, char *why, size_t len)
{
	static const u16 rom_versions[] = {
		[EM7180_FW_ROM_DI01] = EM7180_ROM_VERSION_DI01,
		[EM7180_FW_ROM_DI02] = EM7180_ROM_VERSION_DI02,
	};
	const struct em7180_fw_header *hdr = (const void *)image;
	unsigned int magic, text_len, rom_exp;

	if (size < sizeof(*hdr)) {
		snprintf(why, len, "%zu bytes, shorter than the %zu-byte header",
			 size, sizeof(*hdr));
		return -EINVAL;
	}

	magic = le16_to_cpu(hdr->magic);
	if (magic != EM7180_FW_MAGIC) {
		snprintf(why, len, "bad magic 0x%04x (expected 0x%04x): not a SENtral .fw image",
			 magic, EM7180_FW_MAGIC);
		return -EINVAL;
	}

	text_len = le16_to_cpu(hdr->text_length);
	if (!text_len || text_len % 4) {
		snprintf(why, len, "text length %u is not a whole number of 32-bit words",
			 text_len);
		return -EINVAL;
	}
	if (size - sizeof(*hdr) < text_len) {
		snprintf(why, len, "truncated: %zu bytes of text, the header says %u",
			 size - sizeof(*hdr), text_len);
		return -EINVAL;
	}

	rom_exp = FIELD_GET(EM7180_FW_FLAGS_ROM_MASK, le16_to_cpu(hdr->flags));
	if (rom_exp == EM7180_FW_ROM_ANY)
		return 0;
	if (rom_exp >= ARRAY_SIZE(rom_versions)) {
		snprintf(why, len, "built for unknown ROM code %u, the chip has ROM 0x%04x",
			 rom_exp, rom);
		return -EINVAL;
	}
	if (rom != rom_versions[rom_exp]) {
		snprintf(why, len, "built for ROM DI%02u (0x%04x), the chip has ROM 0x%04x",
			 rom_exp, rom_versions[rom_exp], rom);
		return -EINVAL;
	}

	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_fw_check);

/*
 * The text of a checked image to RAM address 0, then CRCHost. Whatever
 * happens the chip is left out of upload mode. HostControl is written
 * around the register cache, which keeps what resume writes back.
 *
 * Return: 0, -EBADMSG with @crc the chip's CRC on a mismatch, or the bus
 * error.
 */
static int em7180_upload_text(struct em7180_data *data, u32 *crc)
{
	const struct em7180_fw_header *hdr = (const void *)data->fw->data;
	const u8 *text = data->fw->data + sizeof(*hdr);
	unsigned int text_len = le16_to_cpu(hdr->text_length);
	struct regmap *map = data->regmap;
	__be16 addr = cpu_to_be16(0);
	unsigned int off, i, n;
	__le32 chip_crc;
	int ret, err;

	lockdep_assert_held(&data->lock);

	__be32 *buf __free(kfree) = kmalloc(EM7180_UPLOAD_CHUNK, GFP_KERNEL);
	if (!buf)
		return -ENOMEM;

	regcache_cache_bypass(map, true);

	/* UploadAddress, most significant byte first, then upload mode */
	ret = regmap_bulk_write(map, EM7180_REG_UPLOAD_ADDR, &addr, sizeof(addr));
	if (!ret)
		ret = regmap_write(map, EM7180_REG_HOST_CTRL, EM7180_HOST_CTRL_UPLOAD);

	for (off = 0; !ret && off < text_len; off += n) {
		n = min(text_len - off, EM7180_UPLOAD_CHUNK);
		for (i = 0; i < n / 4; i++)
			buf[i] = cpu_to_be32(get_unaligned_le32(text + off + 4 * i));
		ret = regmap_noinc_write(map, EM7180_REG_UPLOAD_DATA, buf, n);
	}

	/* Read before upload mode ends, as em718x_core.c does */
	if (!ret)
		ret = regmap_bulk_read(map, EM7180_REG_CRC_HOST, &chip_crc, sizeof(chip_crc));

	err = regmap_write(map, EM7180_REG_HOST_CTRL, 0);
	regcache_cache_bypass(map, false);
	if (err)
		dev_err(data->dev, "chip left in upload mode: %d\n", err);
	if (ret)
		return ret;
	if (err)
		return err;

	*crc = le32_to_cpu(chip_crc);
	if (*crc != le32_to_cpu(hdr->text_crc))
		return -EBADMSG;

	dev_info(data->dev, "firmware %s uploaded (%u bytes, CRC 0x%08x)\n",
		 data->fw_name, text_len, *crc);
	return 0;
}

/**
 * em7180_upload() - upload the firmware again after a reset
 * @data: driver state, its lock held
 * @ret: what waiting for the EEPROM's firmware gave: 0, or -ENODEV when
 *	 the board has none
 *
 * Without an image loaded at probe (a board with an EEPROM and no
 * firmware-name) nothing changes.
 *
 * Return: @ret without an image, else 0 or a negative error code.
 */
int em7180_upload(struct em7180_data *data, int ret)
{
	const struct em7180_fw_header *hdr;
	u32 crc;

	if (!data->fw)
		return ret;

	ret = em7180_upload_text(data, &crc);
	if (ret == -EBADMSG) {
		hdr = (const void *)data->fw->data;
		dev_err(data->dev,
			"firmware %s: CRC mismatch: the chip computed 0x%08x over the text it received, the header says 0x%08x\n",
			data->fw_name, crc, le32_to_cpu(hdr->text_crc));
	} else if (ret) {
		dev_err(data->dev, "firmware %s: upload failed: %d\n", data->fw_name, ret);
	}

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_upload);

static void em7180_fw_release(void *fw)
{
	release_firmware(fw);
}

/**
 * em7180_upload_probe() - load, check and upload the firmware at probe
 * @data: driver state
 * @no_eeprom: SentralStatus says the board has no EEPROM
 *
 * The image is the devicetree's firmware-name, or em7180.fw when the board
 * has no EEPROM. A firmware-name replaces the EEPROM's firmware too.
 *
 * Return: 0 (also when no upload is needed) or a negative error code,
 * said in the log.
 */
int em7180_upload_probe(struct em7180_data *data, bool no_eeprom)
{
	const char *name = EM7180_FW_DEFAULT_NAME;
	const struct em7180_fw_header *hdr;
	struct device *dev = data->dev;
	const struct firmware *fw;
	char why[96];
	__le16 rom;
	bool named;
	u32 crc;
	int ret;

	named = !device_property_read_string(dev, "firmware-name", &name);
	if (!no_eeprom && !named)
		return 0;

	ret = request_firmware(&fw, name, dev);
	if (ret)
		return dev_err_probe(dev, ret,
				     "cannot load firmware %s%s: install it in the firmware directory (/lib/firmware)\n",
				     name, named ? " (firmware-name)" :
				     ", needed as the board has no EEPROM");

	ret = devm_add_action_or_reset(dev, em7180_fw_release, (void *)fw);
	if (ret)
		return ret;

	guard(em7180)(data);
	ret = regmap_bulk_read(data->regmap, EM7180_REG_ROM_VERSION, &rom, sizeof(rom));
	if (ret)
		return dev_err_probe(dev, ret, "failed to read the ROM version\n");

	ret = em7180_fw_check(fw->data, fw->size, le16_to_cpu(rom), why, sizeof(why));
	if (ret)
		return dev_err_probe(dev, ret, "firmware %s: %s\n", name, why);

	data->fw = fw;
	data->fw_name = name;
	ret = em7180_upload_text(data, &crc);
	if (ret == -EBADMSG) {
		hdr = (const void *)fw->data;
		ret = dev_err_probe(dev, ret,
				    "firmware %s: CRC mismatch: the chip computed 0x%08x over the text it received, the header says 0x%08x\n",
				    name, crc, le32_to_cpu(hdr->text_crc));
	} else if (ret) {
		ret = dev_err_probe(dev, ret, "firmware %s: upload failed\n", name);
	}
	if (ret)
		data->fw = NULL;

	return ret;
}
