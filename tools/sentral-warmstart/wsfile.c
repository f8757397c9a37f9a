// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: saved-file encode, decode, validation and atomic I/O.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <zlib.h>

#include "level.h"
#include "wsfile.h"

static const char *const check_names[] = {
	[SW_CHECK_OK] = "ok",
	[SW_CHECK_TRUNCATED] = "truncated",
	[SW_CHECK_MAGIC] = "wrong magic",
	[SW_CHECK_VERSION] = "unknown version",
	[SW_CHECK_PAYLOAD_SIZE] = "payload size",
	[SW_CHECK_TRAILING] = "trailing data",
	[SW_CHECK_CRC] = "bad CRC",
	[SW_CHECK_FIELD] = "invalid header field",
	[SW_CHECK_NONFINITE] = "non-finite float",
	[SW_CHECK_PRODUCT] = "ProductID mismatch",
	[SW_CHECK_ROM] = "ROM version mismatch",
	[SW_CHECK_RAM] = "RAM version mismatch",
};

const char *sw_check_name(enum sw_file_check c)
{
	if ((unsigned int)c >= sizeof(check_names) / sizeof(check_names[0]))
		return "unknown check";
	return check_names[c];
}

/* Field offsets; the man page's FILE FORMAT table is the same list. */
enum {
	OFF_MAGIC = 0,
	OFF_VERSION = 8,
	OFF_PRODUCT = 10,
	OFF_REVISION = 11,
	OFF_ROM = 12,
	OFF_RAM = 14,
	OFF_STATE = 16,
	OFF_JUDGEMENT = 17,
	OFF_SCORE = 18,
	OFF_TIME = 20,
	OFF_PSIZE = 28,
	OFF_RSVD = 30,
	OFF_PAYLOAD = SW_FILE_HDR_SIZE,
	OFF_CRC = SW_FILE_HDR_SIZE + SW_BLOB_SIZE,
};

size_t sw_file_encode(const struct sw_file *f, uint8_t *buf)
{
	memset(buf, 0, SW_FILE_SIZE);
	memcpy(buf + OFF_MAGIC, SW_FILE_MAGIC, 8);
	sw_put_le16(buf + OFF_VERSION, (uint16_t)f->version);
	buf[OFF_PRODUCT] = f->chip.product_id;
	buf[OFF_REVISION] = f->chip.revision_id;
	sw_put_le16(buf + OFF_ROM, f->chip.rom_version);
	sw_put_le16(buf + OFF_RAM, f->chip.ram_version);
	buf[OFF_STATE] = (uint8_t)f->state;
	if (f->version != SW_FILE_VERSION_1)
		buf[OFF_JUDGEMENT] = (uint8_t)f->judgement;
	sw_put_le16(buf + OFF_SCORE, f->score_raw);
	sw_put_le64(buf + OFF_TIME, f->saved_at);
	sw_put_le16(buf + OFF_PSIZE, SW_BLOB_SIZE);
	memcpy(buf + OFF_PAYLOAD, f->payload, SW_BLOB_SIZE);
	sw_put_le32(buf + OFF_CRC, (uint32_t)crc32(0L, buf, OFF_CRC));
	return SW_FILE_SIZE;
}

int sw_blob_nonfinite(const uint8_t *blob)
{
	int n;

	for (n = 1; n <= SW_NPARAMS; n++)
		if (!isfinite(sw_blob_param(blob, n)))
			return n;
	return 0;
}

#define DETAIL(...) do { \
		if (detail) \
			snprintf(detail, detail_len, __VA_ARGS__); \
	} while (0)

/*
 * Bytes 16..19 and the reserved bytes of a file whose CRC matched: in
 * range for its version, and a score exactly when it was judged by one.
 */
static bool header_ok(const uint8_t *buf, unsigned int version, char *detail,
		      size_t detail_len)
{
	unsigned int state = buf[OFF_STATE], judged = buf[OFF_JUDGEMENT];
	uint16_t score = sw_get_le16(buf + OFF_SCORE);

	if (sw_get_le16(buf + OFF_RSVD)) {
		DETAIL("reserved bytes 30-31 are 0x%04x, not 0",
		       sw_get_le16(buf + OFF_RSVD));
		return false;
	}
	if (version == SW_FILE_VERSION_1) {
		if (state > 3 || judged) {
			DETAIL("calibration status %u or reserved byte 17 (0x%02x) out of range",
			       state, judged);
			return false;
		}
		judged = SW_JUDGED_SCORE;
	} else if (state > SW_LEVEL_MAX || judged > SW_JUDGED_STABLE) {
		DETAIL("calibration level %u or judgement %u out of range",
		       state, judged);
		return false;
	}
	if (judged == SW_JUDGED_SCORE && !sw_score_raw_valid(score)) {
		DETAIL("calibration score raw 0x%04x is below 0 %%", score);
		return false;
	}
	if (judged != SW_JUDGED_SCORE && score) {
		DETAIL("raw score 0x%04x, not 0, with judgement %s", score,
		       sw_judgement_name((enum sw_judgement)judged));
		return false;
	}
	return true;
}

/*
 * The order matters: each check only looks at bytes an earlier check has
 * shown to be present and meaningful, so a truncated file always reports
 * "truncated" and a flipped magic or version byte names that field
 * rather than the CRC that also no longer matches.
 */
enum sw_file_check sw_file_decode(const uint8_t *buf, size_t len,
				  struct sw_file *f, char *detail,
				  size_t detail_len)
{
	uint32_t crc_file, crc_calc;
	unsigned int version, psize;
	int bad;

	if (len < OFF_VERSION) {
		DETAIL("%zu bytes, shorter than the magic", len);
		return SW_CHECK_TRUNCATED;
	}
	if (memcmp(buf + OFF_MAGIC, SW_FILE_MAGIC, 8) != 0) {
		DETAIL("not a sentral-warmstart file (expected \"%s\")",
		       SW_FILE_MAGIC);
		return SW_CHECK_MAGIC;
	}
	if (len < OFF_VERSION + 2) {
		DETAIL("%zu bytes, ends inside the header", len);
		return SW_CHECK_TRUNCATED;
	}
	version = sw_get_le16(buf + OFF_VERSION);
	if (version != SW_FILE_VERSION && version != SW_FILE_VERSION_1) {
		DETAIL("format version %u, this tool reads versions %d and %d",
		       version, SW_FILE_VERSION_1, SW_FILE_VERSION);
		return SW_CHECK_VERSION;
	}
	if (len < SW_FILE_HDR_SIZE) {
		DETAIL("%zu bytes, ends inside the %d-byte header", len,
		       SW_FILE_HDR_SIZE);
		return SW_CHECK_TRUNCATED;
	}
	psize = sw_get_le16(buf + OFF_PSIZE);
	if (psize != SW_BLOB_SIZE) {
		DETAIL("payload size %u, expected %d", psize, SW_BLOB_SIZE);
		return SW_CHECK_PAYLOAD_SIZE;
	}
	if (len < SW_FILE_SIZE) {
		DETAIL("%zu bytes, expected %d", len, SW_FILE_SIZE);
		return SW_CHECK_TRUNCATED;
	}
	if (len > SW_FILE_SIZE) {
		DETAIL("%zu bytes, expected %d", len, SW_FILE_SIZE);
		return SW_CHECK_TRAILING;
	}
	crc_file = sw_get_le32(buf + OFF_CRC);
	crc_calc = (uint32_t)crc32(0L, buf, OFF_CRC);
	if (crc_file != crc_calc) {
		DETAIL("stored 0x%08x, computed 0x%08x", crc_file, crc_calc);
		return SW_CHECK_CRC;
	}
	/*
	 * Only a buggy writer gets past the CRC with these wrong. A score
	 * below 0 % came from a bad read and would look better than any
	 * real calibration to the save policy.
	 */
	if (!header_ok(buf, version, detail, detail_len))
		return SW_CHECK_FIELD;
	bad = sw_blob_nonfinite(buf + OFF_PAYLOAD);
	if (bad) {
		DETAIL("parameter %d (%s) is NaN or infinite", bad,
		       sw_param_name(bad));
		return SW_CHECK_NONFINITE;
	}
	if (f) {
		f->chip.product_id = buf[OFF_PRODUCT];
		f->chip.revision_id = buf[OFF_REVISION];
		f->chip.rom_version = sw_get_le16(buf + OFF_ROM);
		f->chip.ram_version = sw_get_le16(buf + OFF_RAM);
		f->version = (int)version;
		f->state = buf[OFF_STATE];
		f->judgement = version == SW_FILE_VERSION_1 ? SW_JUDGED_SCORE :
			       (enum sw_judgement)buf[OFF_JUDGEMENT];
		f->score_raw = sw_get_le16(buf + OFF_SCORE);
		f->saved_at = sw_get_le64(buf + OFF_TIME);
		memcpy(f->payload, buf + OFF_PAYLOAD, SW_BLOB_SIZE);
	}
	DETAIL("valid");
	return SW_CHECK_OK;
}

enum sw_file_check sw_file_match_chip(const struct sw_file *f,
				      const struct sw_chip_info *chip,
				      char *detail, size_t detail_len)
{
	if (f->chip.product_id != chip->product_id) {
		DETAIL("file 0x%02x, chip 0x%02x", f->chip.product_id,
		       chip->product_id);
		return SW_CHECK_PRODUCT;
	}
	if (f->chip.rom_version != chip->rom_version) {
		DETAIL("file 0x%04x, chip 0x%04x", f->chip.rom_version,
		       chip->rom_version);
		return SW_CHECK_ROM;
	}
	if (f->chip.ram_version != chip->ram_version) {
		DETAIL("file 0x%04x, chip 0x%04x", f->chip.ram_version,
		       chip->ram_version);
		return SW_CHECK_RAM;
	}
	DETAIL("matches");
	return SW_CHECK_OK;
}

const char *sw_judgement_name(enum sw_judgement j)
{
	static const char *const names[] = {
		[SW_JUDGED_NONE] = "none",
		[SW_JUDGED_SCORE] = "score",
		[SW_JUDGED_STABLE] = "stable",
	};

	if ((unsigned int)j >= sizeof(names) / sizeof(names[0]))
		return "?";
	return names[j];
}

int sw_file_level(const struct sw_file *f)
{
	if (f->version != SW_FILE_VERSION_1)
		return f->state;
	return f->state == 3 ? SW_LEVEL_STABLE : SW_LEVEL_CALIBRATING;
}

void sw_file_describe(const struct sw_file *f, char *buf, size_t len)
{
	if (f->version == SW_FILE_VERSION_1)
		snprintf(buf, len, "version 1: status %d, score %.3f%%",
			 f->state, sw_score_pct(f->score_raw));
	else if (f->judgement == SW_JUDGED_SCORE)
		snprintf(buf, len, "level %d (%s), score %.3f%%", f->state,
			 sw_level_name(f->state), sw_score_pct(f->score_raw));
	else if (f->judgement == SW_JUDGED_STABLE)
		snprintf(buf, len, "level %d (%s), no score", f->state,
			 sw_level_name(f->state));
	else
		snprintf(buf, len, "imported from the board's EEPROM");
}

/*
 * The seed's coefficient table (it lists 21 twice; the 35 names below
 * follow its numbering groups: 2 xstates, 6 gparams, 9 nparams,
 * 6 mcoeffs, 6 acoeffs, 6 gcoeffs).
 */
static const char *const param_names[SW_NPARAMS + 1] = {
	NULL,
	"xstates[1]", "xstates[2]",
	"gparams[1]", "gparams[2]", "gparams[3]", "gparams[4]",
	"gparams[5]", "gparams[6]",
	"nparams[1]", "nparams[2]", "nparams[3]", "nparams[4]",
	"nparams[5]", "nparams[6]", "nparams[7]", "nparams[8]",
	"nparams[9]",
	"mcoeffs[1]", "mcoeffs[2]", "mcoeffs[3]", "mcoeffs[4]",
	"mcoeffs[5]", "mcoeffs[6]",
	"acoeffs[1]", "acoeffs[2]", "acoeffs[3]",
	"acoeffs[4]", "acoeffs[5]", "acoeffs[6]",
	"gcoeffs[1]", "gcoeffs[2]", "gcoeffs[3]",
	"gcoeffs[4]", "gcoeffs[5]", "gcoeffs[6]",
};

const char *sw_param_name(int n)
{
	if (n < 1 || n > SW_NPARAMS)
		return "?";
	return param_names[n];
}

/*
 * dir and base of path; base points into path. Trailing slashes are
 * dropped from dir ("DIR/" would make O_NOFOLLOW follow a symlink DIR),
 * and a dir ending in "." or ".." after another component ("link/.") is
 * refused: its last component would not be the directory's own name.
 */
static int split_path(const char *path, char *dir, size_t dir_len,
		      const char **base, struct sw_err *e)
{
	const char *slash = strrchr(path, '/');
	const char *last;

	if (slash) {
		size_t dlen = (size_t)(slash - path);

		while (dlen > 0 && path[dlen - 1] == '/')
			dlen--;
		if (dlen == 0)
			dlen = 1;	/* the root directory */
		if (dlen >= dir_len)
			return sw_err_set(e, SW_EXIT_USAGE, "%s: path too long",
					  path);
		memcpy(dir, path, dlen);
		dir[dlen] = '\0';
		*base = slash + 1;
	} else {
		snprintf(dir, dir_len, ".");
		*base = path;
	}
	if (!**base || strlen(*base) > 200 || !strcmp(*base, ".") ||
	    !strcmp(*base, ".."))
		return sw_err_set(e, SW_EXIT_USAGE, "%s: not a file name", path);
	last = strrchr(dir, '/');
	if (last && last[1] && (!strcmp(last + 1, ".") || !strcmp(last + 1, "..")))
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: name the directory itself, not '%s'",
				  path, last + 1);
	return SW_EXIT_OK;
}

/* Owned by us and writable by nobody else, or why not. */
static int check_owner(const char *what, const char *name,
		       const struct stat *st, struct sw_err *e)
{
	if (st->st_uid != geteuid())
		return sw_err_set(e, SW_EXIT_PERM,
				  "%s: refused: %s owned by uid %u, not uid %u",
				  name, what, (unsigned int)st->st_uid,
				  (unsigned int)geteuid());
	if (st->st_mode & 022)
		return sw_err_set(e, SW_EXIT_PERM,
				  "%s: refused: %s writable by group or others (mode %04o)",
				  name, what, (unsigned int)(st->st_mode & 07777));
	return SW_EXIT_OK;
}

static int open_error(const char *path, int err, int *errno_out,
		      struct sw_err *e)
{
	if (errno_out)
		*errno_out = err;
	if (err == ELOOP)
		return sw_err_set(e, SW_EXIT_PERM,
				  "%s: is a symbolic link; refusing to follow it",
				  path);
	if (err == ENOENT)
		return sw_err_set(e, SW_EXIT_NOFILE, "%s: file does not exist",
				  path);
	return sw_err_set(e, SW_EXIT_IO, "%s: %s", path, strerror(err));
}

/*
 * The directory of a state or --file file, never through a symlink (its
 * last component; the system's own path above it is trusted). Returns the
 * descriptor or -exit code.
 */
static int open_parent(const char *path, const char *dir, bool state,
		       int *errno_out, struct sw_err *e)
{
	struct stat st;
	int dfd, ret;

	dfd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0 && (errno == ELOOP || errno == ENOTDIR)) {
		if (errno_out)
			*errno_out = errno;
		return -sw_err_set(e, SW_EXIT_PERM,
				   "%s: not a directory or a symbolic link; refusing to read through it",
				   dir);
	}
	/* A missing state directory is not a missing file: /var may not be mounted. */
	if (dfd < 0 && errno == ENOENT && state) {
		if (errno_out)
			*errno_out = ENOENT;
		return -sw_err_set(e, SW_EXIT_STATEDIR,
				   "state directory %s does not exist (is its file system mounted?)",
				   dir);
	}
	if (dfd < 0)
		return -open_error(path, errno, errno_out, e);
	if (!state)
		return dfd;
	if (fstat(dfd, &st) < 0) {
		ret = sw_err_set(e, SW_EXIT_IO, "%s: %s", dir, strerror(errno));
		close(dfd);
		return -ret;
	}
	ret = check_owner("directory", dir, &st, e);
	if (ret) {
		close(dfd);
		return -ret;
	}
	return dfd;
}

int sw_file_read(const char *path, enum sw_read_mode mode, uint8_t *buf,
		 size_t *len, int *errno_out, struct sw_err *e)
{
	return sw_file_read_max(path, mode, buf, SW_FILE_MAX_READ, len,
				errno_out, e);
}

int sw_file_read_max(const char *path, enum sw_read_mode mode, uint8_t *buf,
		     size_t max, size_t *len, int *errno_out, struct sw_err *e)
{
	int flags = O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK;
	int dfd = AT_FDCWD, fd, ret;
	const char *base = path;
	char dir[4096];
	struct stat st;
	size_t got = 0;
	ssize_t n;

	if (errno_out)
		*errno_out = 0;
	if (mode != SW_READ_ANY) {
		flags |= O_NOFOLLOW;
		ret = split_path(path, dir, sizeof(dir), &base, e);
		if (ret)
			return ret;
		dfd = open_parent(path, dir, mode == SW_READ_STATE, errno_out, e);
		if (dfd < 0)
			return -dfd;
	}
	fd = openat(dfd, base, flags);
	if (fd < 0) {
		ret = open_error(path, errno, errno_out, e);
		if (dfd >= 0)
			close(dfd);
		return ret;
	}
	if (dfd >= 0)
		close(dfd);
	if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode)) {
		close(fd);
		return sw_err_set(e, SW_EXIT_FILE, "%s: not a regular file",
				  path);
	}
	if (mode != SW_READ_ANY) {
		ret = check_owner("file", path, &st, e);
		if (ret) {
			close(fd);
			return ret;
		}
	}
	/* Read one byte more than allowed to notice an oversized file. */
	while (got < max + 1) {
		n = read(fd, buf + got, max + 1 - got);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0) {
			int err = errno;

			close(fd);
			return sw_err_set(e, SW_EXIT_IO, "%s: read: %s", path,
					  strerror(err));
		}
		if (n == 0)
			break;
		got += (size_t)n;
	}
	close(fd);
	*len = got;
	return SW_EXIT_OK;
}

static int write_all(int fd, const uint8_t *buf, size_t len)
{
	while (len) {
		ssize_t n = write(fd, buf, len);

		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return -1;
		buf += n;
		len -= (size_t)n;
	}
	return 0;
}

static int open_dir(const char *dir, bool state_dir, struct sw_err *e)
{
	struct stat st;
	bool created;
	int dfd, ret;

	/* Only the last component is created: /var/lib must already exist. */
	created = mkdir(dir, 0700) == 0;
	if (!created && errno != EEXIST)
		return -sw_err_set(e, SW_EXIT_IO, "%s: cannot create directory: %s",
				   dir, strerror(errno));
	dfd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0) {
		if (errno == ELOOP || errno == ENOTDIR)
			return -sw_err_set(e, SW_EXIT_PERM,
					   "%s: not a directory or a symbolic link; refusing to write through it",
					   dir);
		return -sw_err_set(e, SW_EXIT_IO, "%s: %s", dir,
				   strerror(errno));
	}
	if (!state_dir)
		return dfd;
	if (fstat(dfd, &st) < 0) {
		ret = sw_err_set(e, SW_EXIT_IO, "%s: %s", dir, strerror(errno));
		close(dfd);
		return -ret;
	}
	/* Someone else's directory: they could swap the file after us. */
	if (st.st_uid != geteuid()) {
		close(dfd);
		return -sw_err_set(e, SW_EXIT_PERM,
				   "%s: refused: directory owned by uid %u, not uid %u",
				   dir, (unsigned int)st.st_uid,
				   (unsigned int)geteuid());
	}
	/*
	 * Saved calibrations are root's business alone, but a directory the
	 * tool did not create (--state-dir /var/lib, say) is not its to
	 * change: refuse rather than chmod it under other services.
	 */
	if (!created && (st.st_mode & 077)) {
		close(dfd);
		return -sw_err_set(e, SW_EXIT_PERM,
				   "%s: refused: group or others have access (mode %04o); a state directory must be 0700 (chmod 0700 %s if it holds nothing else)",
				   dir, (unsigned int)(st.st_mode & 07777), dir);
	}
	return dfd;
}

/*
 * A temporary name of ours: ".BASE.XXXXXXXX.tmp" with 8 hex digits.
 */
static bool is_our_temp(const char *name, const char *base)
{
	size_t bl = strlen(base), nl = strlen(name), i;

	if (nl != 1 + bl + 1 + 8 + 4 || name[0] != '.' ||
	    strncmp(name + 1, base, bl) || name[1 + bl] != '.' ||
	    strcmp(name + nl - 4, ".tmp"))
		return false;
	for (i = 2 + bl; i < 2 + bl + 8; i++)
		if (!strchr("0123456789abcdef", name[i]))
			return false;
	return true;
}

/* A killed save's temporary file is older than this; a live one is locked. */
#define STALE_TEMP_S 2

/*
 * Remove temporary files a killed save left behind: regular files of our
 * name pattern, ours, not locked by a save still running (each holds an
 * flock on its temporary file until the rename) and not brand new (the
 * instant between a save's create and its lock).
 */
static void remove_stale_temps(int dfd, const char *base)
{
	struct dirent *de;
	int fd, dup_fd;
	struct stat st;
	DIR *d;

	dup_fd = dup(dfd);
	if (dup_fd < 0)
		return;
	d = fdopendir(dup_fd);
	if (!d) {
		close(dup_fd);
		return;
	}
	while ((de = readdir(d))) {
		if (!is_our_temp(de->d_name, base))
			continue;
		fd = openat(dfd, de->d_name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK |
			    O_CLOEXEC | O_NOCTTY);
		if (fd < 0)
			continue;
		if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
		    st.st_uid == geteuid() &&
		    st.st_mtime + STALE_TEMP_S < time(NULL) &&
		    flock(fd, LOCK_EX | LOCK_NB) == 0)
			unlinkat(dfd, de->d_name, 0);
		close(fd);
	}
	closedir(d);
}

void sw_file_remove_stale_temps(const char *path)
{
	char dir[4096];
	const char *base;
	struct sw_err e;
	int dfd;

	sw_err_clear(&e);
	if (split_path(path, dir, sizeof(dir), &base, &e))
		return;
	dfd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0)
		return;
	remove_stale_temps(dfd, base);
	close(dfd);
}

int sw_file_write_atomic(const char *path, const uint8_t *buf, size_t len,
			 bool state_dir, struct sw_err *e)
{
	char dir[4096], tmp[300];
	const char *base;
	struct stat st;
	int dfd, fd = -1, i, err;

	err = split_path(path, dir, sizeof(dir), &base, e);
	if (err)
		return err;
	dfd = open_dir(dir, state_dir, e);
	if (dfd < 0)
		return -dfd;

	if (fstatat(dfd, base, &st, AT_SYMLINK_NOFOLLOW) == 0) {
		if (S_ISLNK(st.st_mode)) {
			close(dfd);
			return sw_err_set(e, SW_EXIT_PERM,
					  "%s: is a symbolic link; refusing to replace it",
					  path);
		}
		if (!S_ISREG(st.st_mode)) {
			close(dfd);
			return sw_err_set(e, SW_EXIT_FILE,
					  "%s: exists and is not a regular file",
					  path);
		}
	}
	remove_stale_temps(dfd, base);

	for (i = 0; i < 100 && fd < 0; i++) {
		uint32_t rnd = 0;

		if (getrandom(&rnd, sizeof(rnd), GRND_NONBLOCK) < 0)
			rnd = (uint32_t)getpid() * 2654435761u + (uint32_t)i;
		snprintf(tmp, sizeof(tmp), ".%s.%08x.tmp", base, rnd);
		fd = openat(dfd, tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW |
			    O_CLOEXEC, 0600);
		if (fd < 0 && errno != EEXIST)
			break;
	}
	if (fd < 0) {
		err = errno;
		close(dfd);
		return sw_err_set(e, SW_EXIT_IO, "%s: cannot create a temporary file: %s",
				  dir, strerror(err));
	}
	/*
	 * Held until the rename, so that another save never takes this file
	 * for a killed one's. umask can only remove bits; make 0600 explicit.
	 */
	if (flock(fd, LOCK_EX) < 0 || fchmod(fd, 0600) < 0 ||
	    write_all(fd, buf, len) < 0 || fsync(fd) < 0 ||
	    renameat(dfd, tmp, dfd, base) < 0) {
		err = errno;
		goto fail;
	}
	close(fd);
	/* The rename is durable only once the directory is on disk too. */
	if (fsync(dfd) < 0) {
		err = errno;
		close(dfd);
		return sw_err_set(e, SW_EXIT_IO, "%s: fsync: %s", dir,
				  strerror(err));
	}
	close(dfd);
	return SW_EXIT_OK;

fail:
	unlinkat(dfd, tmp, 0);
	close(fd);
	close(dfd);
	return sw_err_set(e, SW_EXIT_IO, "%s: write failed: %s", path,
			  strerror(err));
}

#define LOCK_SUFFIX ".lock"

void sw_file_lock_name(const char *path, char *out, size_t len)
{
	const char *slash = strrchr(path, '/');

	if (slash)
		snprintf(out, len, "%.*s.%s" LOCK_SUFFIX,
			 (int)(slash - path + 1), path, slash + 1);
	else
		snprintf(out, len, ".%s" LOCK_SUFFIX, path);
}

int sw_file_lock_open(const char *path, bool state_dir, struct sw_err *e)
{
	char dir[4096], name[300], lock[4400];
	const char *base;
	struct stat st;
	int dfd, fd, err;

	err = split_path(path, dir, sizeof(dir), &base, e);
	if (err)
		return -err;
	dfd = open_dir(dir, state_dir, e);
	if (dfd < 0)
		return dfd;
	snprintf(name, sizeof(name), ".%s" LOCK_SUFFIX, base);
	fd = openat(dfd, name, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC |
		    O_NOCTTY | O_NONBLOCK, 0600);
	err = errno;
	close(dfd);
	sw_file_lock_name(path, lock, sizeof(lock));
	if (fd < 0 && err == ELOOP)
		return -sw_err_set(e, SW_EXIT_PERM,
				   "%s: is a symbolic link; refusing to follow it",
				   lock);
	if (fd < 0)
		return -sw_err_set(e, SW_EXIT_IO, "%s: %s", lock, strerror(err));
	/* Someone else's lock file could be held for ever, or be a FIFO. */
	if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode) ||
	    st.st_uid != geteuid()) {
		close(fd);
		return -sw_err_set(e, SW_EXIT_PERM,
				   "%s: refused: not a regular file of uid %u",
				   lock, (unsigned int)geteuid());
	}
	return fd;
}

bool sw_file_lock_try(int fd)
{
	return flock(fd, LOCK_EX | LOCK_NB) == 0;
}

int sw_file_rename(const char *from, const char *to, bool replace,
		   struct sw_err *e)
{
	char dir[4096], dir2[4096];
	const char *base, *base2;
	struct stat st;
	int dfd, ret;

	ret = split_path(from, dir, sizeof(dir), &base, e);
	ret = ret ? ret : split_path(to, dir2, sizeof(dir2), &base2, e);
	if (ret)
		return ret;
	if (strcmp(dir, dir2))
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s and %s are not in one directory", from, to);
	dfd = open_parent(from, dir, true, NULL, e);
	if (dfd < 0)
		return -dfd;
	if (fstatat(dfd, base, &st, AT_SYMLINK_NOFOLLOW) < 0 ||
	    !S_ISREG(st.st_mode)) {
		ret = sw_err_set(e, SW_EXIT_FILE, "%s: not a regular file", from);
		goto out;
	}
	if (renameat2(dfd, base, dfd, base2, replace ? 0 : RENAME_NOREPLACE) < 0) {
		ret = sw_err_set(e, SW_EXIT_IO, "renaming %s to %s: %s", from,
				 to, strerror(errno));
		goto out;
	}
	if (fsync(dfd) < 0)
		ret = sw_err_set(e, SW_EXIT_IO, "%s: fsync: %s", dir,
				 strerror(errno));
out:
	close(dfd);
	return ret;
}
