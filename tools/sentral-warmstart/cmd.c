// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: status, save, restore and show.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "board.h"
#include "cmd.h"
#include "policy.h"
#include "wsfile.h"

/* How long restore waits for calibration_status to become 3. */
#define RESTORE_SETTLE_MS 2000
#define RESTORE_POLL_MS 20

static uint64_t real_now_ms(void *clk)
{
	struct timespec ts;

	(void)clk;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

static void real_sleep_ms(void *clk, unsigned int ms)
{
	struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };

	(void)clk;
	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

/*
 * The three signals are blocked but while asleep in ppoll(), so that one
 * that comes just before the sleep still ends it.
 */
static void real_nap_ms(void *clk, unsigned int ms)
{
	struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000L };
	sigset_t block, old;

	(void)clk;
	sigemptyset(&block);
	sigaddset(&block, SIGINT);
	sigaddset(&block, SIGTERM);
	sigaddset(&block, SIGHUP);
	sigprocmask(SIG_BLOCK, &block, &old);
	if (!sw_signal_pending())
		ppoll(NULL, 0, &ts, &old);
	sigprocmask(SIG_SETMASK, &old, NULL);
}

static uint64_t real_wall_s(void *clk)
{
	(void)clk;
	return (uint64_t)time(NULL);
}

void sw_env_init(struct sw_env *env, FILE *out, FILE *err)
{
	memset(env, 0, sizeof(*env));
	env->out = out;
	env->err = err;
	env->now_ms = real_now_ms;
	env->sleep_ms = real_sleep_ms;
	env->nap_ms = real_nap_ms;
	env->wall_s = real_wall_s;
}

/*
 * udev logs a RUN program's output only at debug level: put what matters
 * into the kernel log, where a boot's story is read.
 */
static void to_kmsg(int level, const char *msg)
{
	char line[700];
	int fd, n;

	fd = open("/dev/kmsg", O_WRONLY | O_CLOEXEC | O_NOCTTY);
	if (fd < 0)
		return;
	n = snprintf(line, sizeof(line), "<%d>sentral-warmstart[%d]: %s\n",
		     level, (int)getpid(), msg);
	if (n > 0 && write(fd, line, (size_t)n) < 0)
		n = 0;	/* the log is best effort */
	close(fd);
}

void sw_note(struct sw_env *env, const char *fmt, ...)
{
	char msg[600];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	fprintf(env->out, "%s\n", msg);
	fflush(env->out);
	if (env->kmsg)
		to_kmsg(5, msg);
}

void sw_report(struct sw_env *env, const struct sw_err *e)
{
	fprintf(env->err, "sentral-warmstart: error: %s\n", e->msg);
	fflush(env->err);
	if (env->kmsg) {
		char msg[560];

		snprintf(msg, sizeof(msg), "error: %s", e->msg);
		to_kmsg(3, msg);
	}
}

void sw_file_path(const struct sw_opts *o, const struct sw_backend *b,
		  char *out, size_t len)
{
	if (o->file)
		snprintf(out, len, "%s", o->file);
	else
		snprintf(out, len, "%s/%s.ws", o->state_dir, b->key);
}

static void fmt_time(uint64_t t, char *buf, size_t len)
{
	time_t tt = (time_t)t;
	struct tm tm;

	/* Beyond INT64_MAX the cast turns a file's time into one before 1970. */
	if (tt < 0 || !gmtime_r(&tt, &tm) ||
	    !strftime(buf, len, "%Y-%m-%dT%H:%M:%SZ", &tm))
		snprintf(buf, len, "?");
}

/*
 * The state file is trusted only in a directory that is ours alone; a file
 * named with --file must still be ours (see enum sw_read_mode).
 */
static enum sw_read_mode read_mode(const struct sw_opts *o)
{
	return o->file ? SW_READ_OWNED : SW_READ_STATE;
}

/*
 * Load the existing file at path, if any. Returns SW_EXIT_OK with
 * *have = true and *f filled when it is valid and made for this chip;
 * SW_EXIT_OK with *have = false when it is missing or not usable (why
 * says which); an error only when it must not be touched at all. errno_out
 * receives the errno of a failed open.
 */
static int load_existing(const struct sw_opts *o, const char *path,
			 const struct sw_chip_info *chip, struct sw_file *f,
			 bool *have, char *why, size_t why_len, int *errno_out,
			 struct sw_err *e)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	enum sw_file_check c;
	struct sw_err rerr;
	char detail[160];
	size_t len;
	int ret;

	*have = false;
	why[0] = '\0';
	sw_err_clear(&rerr);
	ret = sw_file_read(path, read_mode(o), buf, &len, errno_out, &rerr);
	if (ret == SW_EXIT_NOFILE)
		return SW_EXIT_OK;
	if (ret)
		return sw_err_set(e, rerr.code, "%s", rerr.msg);
	c = sw_file_decode(buf, len, f, detail, sizeof(detail));
	if (c == SW_CHECK_OK && chip)
		c = sw_file_match_chip(f, chip, detail, sizeof(detail));
	if (c != SW_CHECK_OK) {
		snprintf(why, why_len, "%s (%s)", sw_check_name(c), detail);
		return SW_EXIT_OK;
	}
	*have = true;
	return SW_EXIT_OK;
}

static bool exists(const char *path)
{
	struct stat st;

	return lstat(path, &st) == 0;
}

/* STATE_DIR/KEY.ws for a legacy key, or false when there is none. */
static bool legacy_path(const struct sw_opts *o, const struct sw_backend *b,
			int i, char *out, size_t len)
{
	const char *k = b->legacy_key[i];

	if (!k[0] || !strcmp(k, b->key))
		return false;
	snprintf(out, len, "%s/%s.ws", o->state_dir, k);
	return exists(out);
}

/*
 * Earlier versions keyed files by udev's ID_PATH or the I2C client's
 * name: move a file saved under one of those to the new key, once. Only the commands
 * that write the state directory do; a failure is reported and the file
 * is left where it is (it cannot be lost).
 */
static void migrate_legacy(const struct sw_backend *b, const struct sw_opts *o,
			   struct sw_env *env)
{
	char path[4096], old[4096];
	struct sw_err me;
	int i;

	if (o->file)
		return;
	sw_file_path(o, b, path, sizeof(path));
	if (exists(path))
		return;
	for (i = 0; i < SW_NLEGACY; i++) {
		if (!legacy_path(o, b, i, old, sizeof(old)))
			continue;
		sw_err_clear(&me);
		if (sw_file_rename(old, path, false, &me))
			sw_note(env, "warning: not migrating %s to %s: %s", old,
				path, me.msg);
		else
			sw_note(env, "migrated %s to %s (the key of %s is now %s)",
				old, path, b->name, b->key);
		return;
	}
}

/* The accel offsets of a blob (parameters 27..29) in LSB. */
static void blob_offsets(const uint8_t *blob, int lsb[3])
{
	int k;

	for (k = 0; k < 3; k++)
		lsb[k] = sw_g_to_lsb(sw_blob_param(blob, SW_PARAM_ACCEL_X + k));
}

/*
 * See struct sw_policy_in. Zero is what a chip holds from power-on until a
 * restore: a chip that was not restored must not overwrite saved offsets.
 */
static bool offsets_differ(const int chip[3], bool have_old,
			   const struct sw_file *old)
{
	static const int zero[3];
	int file[3];

	if (!memcmp(chip, zero, sizeof(zero)))
		return false;
	if (!have_old)
		return true;
	blob_offsets(old->payload, file);
	return memcmp(chip, file, sizeof(file)) != 0;
}

/*
 * The policy's answer for a calibration state, against the file at path
 * it would replace. The chip's accel offsets come from blob, or when it is
 * NULL from the driver's copy (no transfer). chip receives the chip's
 * identity, old the file (when *what is SW_SAVE_OFFSETS), oldwhy why an
 * existing file is unusable ("" when it is fine or missing).
 */
static int policy_for(struct sw_backend *b, const struct sw_opts *o,
		      const struct sw_cal_state *cs, const uint8_t *blob,
		      struct sw_chip_info *chip, const char *path,
		      struct sw_file *old, enum sw_save_what *what, char *why,
		      size_t why_len, char *oldwhy, size_t oldwhy_len,
		      struct sw_err *e)
{
	struct sw_policy_in pin = { 0 };
	struct sw_err lerr;
	int ret, lsb[3];

	ret = b->ops->chip_info(b, chip, e);
	if (ret)
		return ret;
	sw_err_clear(&lerr);
	memset(old, 0, sizeof(*old));
	ret = load_existing(o, path, chip, old, &pin.have_old, oldwhy,
			    oldwhy_len, NULL, &lerr);
	/* A missing state directory is created by the write. */
	if (ret && ret != SW_EXIT_STATEDIR)
		return sw_err_set(e, ret, "%s", lerr.msg);

	if (blob) {
		blob_offsets(blob, lsb);
		pin.offsets_differ = offsets_differ(lsb, pin.have_old, old);
	} else {
		sw_err_clear(&lerr);
		ret = b->ops->accel_offset_get(b, lsb, &lerr);
		/* Offsets the driver cannot tell are left to the next save. */
		if (ret == SW_EXIT_DEVICE)
			return sw_err_set(e, ret, "%s", lerr.msg);
		pin.offsets_differ = !ret &&
				     offsets_differ(lsb, pin.have_old, old);
	}
	pin.status = cs->status;
	pin.score_raw = cs->score_raw;
	pin.max_score = o->max_score;
	pin.old_status = old->cal_status;
	pin.old_score_raw = old->score_raw;
	pin.force = o->force;
	pin.improve_only = o->improve_only;
	pin.margin = o->margin;
	*what = sw_policy_save(&pin, why, why_len);
	return SW_EXIT_OK;
}

int sw_save_wanted(struct sw_backend *b, const struct sw_opts *o,
		   const struct sw_cal_state *cs, bool *yes, char *why,
		   size_t len, struct sw_err *e)
{
	enum sw_save_what what = SW_SAVE_NOTHING;
	struct sw_chip_info chip;
	char path[4096], oldwhy[256];
	struct sw_file old;
	int ret;

	sw_file_path(o, b, path, sizeof(path));
	ret = policy_for(b, o, cs, NULL, &chip, path, &old, &what, why, len,
			 oldwhy, sizeof(oldwhy), e);
	*yes = !ret && what != SW_SAVE_NOTHING;
	return ret;
}

/*
 * Take the lock of path's writers, waiting for another one at most
 * SW_LOCK_WAIT_MS. Returns the descriptor that holds it, or an exit code
 * negated.
 */
static int writers_lock(const struct sw_opts *o, struct sw_env *env,
			const char *path, struct sw_err *e)
{
	uint64_t start = env->now_ms(env->clk);
	char lock[4400];
	int fd;

	fd = sw_file_lock_open(path, !o->file, e);
	if (fd < 0)
		return fd;
	while (!sw_file_lock_try(fd)) {
		if (env->now_ms(env->clk) - start >= SW_LOCK_WAIT_MS) {
			close(fd);
			sw_file_lock_name(path, lock, sizeof(lock));
			return -sw_err_set(e, SW_EXIT_IO,
					   "%s: another writer of %s (watch, save, calibrate, accel-cal or restore) has held it for %d s; not writing",
					   lock, path, SW_LOCK_WAIT_MS / 1000);
		}
		env->sleep_ms(env->clk, 50);
	}
	return fd;
}

/* The payload and header to write for the policy's answer. */
static void new_file(enum sw_save_what what, const struct sw_cal_state *cs,
		     const uint8_t *blob, const struct sw_file *old,
		     struct sw_file *nf)
{
	int k;

	if (what == SW_SAVE_OFFSETS) {
		nf->cal_status = old->cal_status;
		nf->score_raw = old->score_raw;
		memcpy(nf->payload, old->payload, SW_BLOB_SIZE);
		for (k = 0; k < 3; k++)
			sw_blob_set_param(nf->payload, SW_PARAM_ACCEL_X + k,
					  sw_blob_param(blob,
							SW_PARAM_ACCEL_X + k));
		return;
	}
	nf->cal_status = cs->status;
	nf->score_raw = cs->score_raw;
	memcpy(nf->payload, blob, SW_BLOB_SIZE);
}

/* Under the writers' lock: the policy's look at the file, then the write. */
static int save_locked(struct sw_backend *b, const struct sw_opts *o,
		       struct sw_env *env, const struct sw_cal_state *cs,
		       const uint8_t *blob, const char *path, bool *saved,
		       struct sw_err *e)
{
	uint8_t out[SW_FILE_SIZE];
	enum sw_save_what what = SW_SAVE_NOTHING;
	char why[512], oldwhy[256];
	struct sw_file nf, old;
	int ret, lsb[3];

	migrate_legacy(b, o, env);
	memset(&nf, 0, sizeof(nf));
	ret = policy_for(b, o, cs, blob, &nf.chip, path, &old, &what, why,
			 sizeof(why), oldwhy, sizeof(oldwhy), e);
	if (ret)
		return ret;
	/* The policy saying no is the policy working: not a failure. */
	if (what == SW_SAVE_NOTHING) {
		sw_note(env, "not saving %s calibration to %s: %s", b->name,
			path, why);
		return SW_EXIT_OK;
	}
	if (oldwhy[0])
		sw_note(env, "replacing unusable %s: %s", path, oldwhy);
	new_file(what, cs, blob, &old, &nf);
	nf.saved_at = env->wall_s(env->clk);
	sw_file_encode(&nf, out);
	ret = sw_file_write_atomic(path, out, sizeof(out), !o->file, e);
	if (ret)
		return ret;
	blob_offsets(blob, lsb);
	if (what == SW_SAVE_OFFSETS)
		sw_note(env, "saved %s accel offsets %d %d %d LSB to %s: %s",
			b->name, lsb[0], lsb[1], lsb[2], path, why);
	else
		sw_note(env, "saved %s calibration to %s: %s", b->name, path,
			why);
	*saved = true;
	return SW_EXIT_OK;
}

int sw_save_snapshot(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, const struct sw_cal_state *cs,
		     const uint8_t *blob, bool *saved, struct sw_err *e)
{
	char path[4096], why[256];
	bool wrote = false;
	int bad, ret, lock;

	if (saved)
		*saved = false;
	if (!sw_cal_state_check(cs, why, sizeof(why)))
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: %s, read from the chip: not saving",
				  b->name, why);
	bad = sw_blob_nonfinite(blob);
	if (bad)
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: parameter %d (%s) read from the chip is not a finite number; not saving",
				  b->name, bad, sw_param_name(bad));
	sw_file_path(o, b, path, sizeof(path));
	lock = writers_lock(o, env, path, e);
	if (lock < 0)
		return -lock;
	ret = save_locked(b, o, env, cs, blob, path, &wrote, e);
	close(lock);
	if (saved)
		*saved = wrote;
	return ret;
}

/*
 * What import-board records where the board's block has nothing: no
 * calibration status or score were saved with it. Status 0 and the worst
 * score (as for a firmware that does not report them): restore does not
 * wait for status 3, and any calibration the chip completes later is
 * better by the save policy, so save and watch replace the import.
 */
#define IMPORT_STATUS 0
#define IMPORT_SCORE_RAW 0xffff

/* Under the writers' lock: the import policy's look at the file, the write. */
static int import_locked(struct sw_backend *b, const struct sw_opts *o,
			 struct sw_env *env, const struct sw_board_cal *cal,
			 const char *path, struct sw_err *e)
{
	struct sw_policy_in pin = { 0 };
	uint8_t out[SW_FILE_SIZE];
	char why[512], oldwhy[256];
	struct sw_file nf, old;
	struct sw_err lerr;
	int ret;

	migrate_legacy(b, o, env);
	memset(&nf, 0, sizeof(nf));
	ret = b->ops->chip_info(b, &nf.chip, e);
	if (ret)
		return ret;
	sw_err_clear(&lerr);
	ret = load_existing(o, path, &nf.chip, &old, &pin.have_old, oldwhy,
			    sizeof(oldwhy), NULL, &lerr);
	/* A missing state directory is created by the write. */
	if (ret && ret != SW_EXIT_STATEDIR)
		return sw_err_set(e, ret, "%s", lerr.msg);
	pin.old_status = old.cal_status;
	pin.old_score_raw = old.score_raw;
	pin.force = o->force;
	if (!sw_policy_import(&pin, why, sizeof(why))) {
		sw_note(env, "not importing the board's calibration for %s to %s: %s",
			b->name, path, why);
		return SW_EXIT_OK;
	}
	if (oldwhy[0])
		sw_note(env, "replacing unusable %s: %s", path, oldwhy);
	nf.cal_status = IMPORT_STATUS;
	nf.score_raw = IMPORT_SCORE_RAW;
	nf.saved_at = env->wall_s(env->clk);
	memcpy(nf.payload, cal->blob, SW_BLOB_SIZE);
	sw_file_encode(&nf, out);
	ret = sw_file_write_atomic(path, out, sizeof(out), !o->file, e);
	if (ret)
		return ret;
	sw_note(env, "imported %s's calibration from the board's EEPROM (%s layout, parameters at 0x%04x) to %s: %s",
		b->name, sw_board_layout_name(cal->layout), cal->params_at,
		path, why);
	return SW_EXIT_OK;
}

/* The utilities' accel cal is reported, not imported (see the man page). */
static void note_board_accel(struct sw_env *env, const struct sw_board_cal *cal)
{
	if (!cal->accel_present) {
		sw_note(env, "the board holds no accel calibration");
		return;
	}
	sw_note(env, "the board's accel calibration (max/min LSB: x %d/%d, y %d/%d, z %d/%d)%s is not imported: the utilities apply it through registers of their firmware, not through warm-start parameters 27-29; run accel-cal for this tool's offsets",
		cal->acc_max[0], cal->acc_min[0], cal->acc_max[1],
		cal->acc_min[1], cal->acc_max[2], cal->acc_min[2],
		cal->accel_in_range ? "" :
		" is out of the utility's own bounds (1800..2240 LSB) and");
}

int sw_cmd_import_board(struct sw_backend *b, const struct sw_opts *o,
			struct sw_env *env, struct sw_err *e)
{
	struct sw_board_cal cal;
	enum sw_board_check c;
	struct sw_err rerr;
	char path[4096], detail[300];
	uint8_t *img;
	size_t len;
	int ret, lock;

	img = malloc(SW_BOARD_EEPROM_SIZE + 1);
	if (!img)
		return sw_err_set(e, SW_EXIT_OSERR, "out of memory");
	/*
	 * The image the administrator names, as show reads a file: at24's
	 * nvmem file lies under a symlinked directory. What it holds is
	 * checked below before anything is written.
	 */
	sw_err_clear(&rerr);
	ret = sw_file_read_max(o->image, SW_READ_ANY, img, SW_BOARD_EEPROM_SIZE,
			       &len, NULL, &rerr);
	if (ret == SW_EXIT_NOFILE)
		ret = sw_err_set(e, ret, "EEPROM image %s does not exist",
				 o->image);
	else if (ret)
		ret = sw_err_set(e, rerr.code, "%s", rerr.msg);
	if (!ret) {
		c = sw_board_parse(img, len, o->layout, &cal, detail,
				   sizeof(detail));
		if (c != SW_BOARD_OK)
			ret = sw_err_set(e, SW_EXIT_FILE,
					 "%s: refused: %s (%s); nothing written",
					 o->image, sw_board_check_name(c),
					 detail);
	}
	free(img);
	if (ret)
		return ret;
	sw_file_path(o, b, path, sizeof(path));
	lock = writers_lock(o, env, path, e);
	if (lock < 0)
		return -lock;
	ret = import_locked(b, o, env, &cal, path, e);
	close(lock);
	if (!ret)
		note_board_accel(env, &cal);
	return ret;
}

/* The RAM version for a message: "0x0d17", or "unknown". */
static void ram_str(struct sw_backend *b, char *buf, size_t len)
{
	struct sw_chip_info ci;
	struct sw_err ie;

	sw_err_clear(&ie);
	if (b->ops->chip_info(b, &ci, &ie) == SW_EXIT_OK)
		snprintf(buf, len, "0x%04x", ci.ram_version);
	else
		snprintf(buf, len, "unknown");
}

int sw_err_not_reported(struct sw_backend *b, const char *what,
			struct sw_err *e)
{
	char ram[16];

	ram_str(b, ram, sizeof(ram));
	return sw_err_set(e, SW_EXIT_DRIVER,
			  "%s: the em7180 driver does not report the calibration status and score of this firmware (RAM %s): %s; if the firmware does report them (in registers 0x43, 0x44 and 0x4D-0x4E), name its RAM version in the device's emmicro,calibration-firmware property or em7180_core.calibration_firmware",
			  b->name, ram, what);
}

int sw_save_now(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, bool *saved, struct sw_err *e)
{
	struct sw_cal_state before, after;
	uint8_t blob[SW_BLOB_SIZE];
	char why[160];
	int i, ret;

	ret = b->ops->cal_state(b, &before, e);
	if (!ret && !before.reported && !o->force)
		return sw_err_not_reported(b, "not saving (save --force saves anyway)",
					   e);
	ret = ret ? ret : b->ops->read_blob(b, blob, e);
	ret = ret ? ret : b->ops->cal_state(b, &after, e);
	if (ret)
		return ret;
	for (i = 0; i < 2; i++)
		if (!sw_cal_state_check(i ? &after : &before, why, sizeof(why)))
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: %s, read from the chip: not saving",
					  b->name, why);
	/*
	 * The blob must be judged by the state it was taken in: if the
	 * calibration changed under the read, judge by the worse of the two.
	 */
	if (after.status < before.status ||
	    (after.status == before.status &&
	     after.score_raw > before.score_raw))
		before = after;
	return sw_save_snapshot(b, o, env, &before, blob, saved, e);
}

int sw_cmd_save(struct sw_backend *b, const struct sw_opts *o,
		struct sw_env *env, struct sw_err *e)
{
	return sw_save_now(b, o, env, NULL, e);
}

/*
 * A state file that failed a check is kept for inspection under
 * KEY.ws.refused (replacing an older one), so that the next save can write
 * a good calibration in its place: under the writers' lock, and only while
 * it still holds the len bytes of buf that were refused (a save may have
 * replaced it meanwhile). A --file file is the user's: left alone.
 */
static void set_aside(const struct sw_opts *o, struct sw_env *env,
		      const char *path, const uint8_t *buf, size_t len,
		      char *note, size_t note_len)
{
	uint8_t now[SW_FILE_MAX_READ + 1];
	char aside[4200];
	struct sw_err me;
	size_t now_len;
	int lock;

	note[0] = '\0';
	if (o->file)
		return;
	snprintf(aside, sizeof(aside), "%s.refused", path);
	sw_err_clear(&me);
	lock = writers_lock(o, env, path, &me);
	if (lock < 0) {
		snprintf(note, note_len, "; could not move it aside: %s", me.msg);
		return;
	}
	if (sw_file_read(path, read_mode(o), now, &now_len, NULL, &me) ||
	    now_len != len || memcmp(now, buf, len))
		snprintf(note, note_len,
			 "; not moved aside: it changed meanwhile (a save replaced it?)");
	else if (sw_file_rename(path, aside, true, &me))
		snprintf(note, note_len, "; could not move it aside: %s", me.msg);
	else
		snprintf(note, note_len, "; moved aside to %s for inspection",
			 aside);
	close(lock);
}

int sw_cmd_restore(struct sw_backend *b, const struct sw_opts *o,
		   struct sw_env *env, struct sw_err *e)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	struct sw_chip_info chip;
	struct sw_cal_state cs;
	enum sw_file_check c;
	struct sw_err rerr;
	char path[4096], detail[160], aside[4400];
	struct sw_file f;
	uint64_t start;
	size_t len;
	int ret;

	migrate_legacy(b, o, env);
	sw_file_path(o, b, path, sizeof(path));
	sw_err_clear(&rerr);
	ret = sw_file_read(path, read_mode(o), buf, &len, NULL, &rerr);
	if (ret == SW_EXIT_NOFILE && o->if_present) {
		sw_note(env, "no saved calibration for %s (%s); nothing to restore",
			b->name, path);
		return SW_EXIT_OK;
	}
	if (ret == SW_EXIT_NOFILE)
		return sw_err_set(e, SW_EXIT_NOFILE,
				  "no saved calibration for %s: %s does not exist",
				  b->name, path);
	if (ret)
		return sw_err_set(e, rerr.code, "%s", rerr.msg);
	c = sw_file_decode(buf, len, &f, detail, sizeof(detail));
	if (c != SW_CHECK_OK) {
		set_aside(o, env, path, buf, len, aside, sizeof(aside));
		return sw_err_set(e, SW_EXIT_FILE,
				  "%s: refused: %s (%s); the chip was not touched%s",
				  path, sw_check_name(c), detail, aside);
	}
	ret = b->ops->chip_info(b, &chip, e);
	if (ret)
		return ret;
	c = sw_file_match_chip(&f, &chip, detail, sizeof(detail));
	if (c != SW_CHECK_OK) {
		if (!o->force) {
			set_aside(o, env, path, buf, len, aside, sizeof(aside));
			return sw_err_set(e, SW_EXIT_FILE,
					  "%s: refused: %s (%s); the chip was not touched (--force restores anyway)%s",
					  path, sw_check_name(c), detail, aside);
		}
		sw_note(env, "warning: %s: %s (%s); restoring anyway (--force)",
			path, sw_check_name(c), detail);
	}
	ret = b->ops->write_blob(b, f.payload, e);
	if (ret)
		return ret;

	/*
	 * The chip needs a moment to take the coefficients in. A file saved
	 * for its accel offsets before the magnetic calibration was complete
	 * cannot bring status 3.
	 */
	start = env->now_ms(env->clk);
	for (;;) {
		ret = b->ops->cal_state(b, &cs, e);
		if (ret)
			return ret;
		if (!cs.reported) {
			sw_note(env, "restored %s calibration from %s (saved with status %d, %.3f%%); the driver does not report the calibration status of this firmware (RAM 0x%04x): not waiting for it",
				b->name, path, f.cal_status,
				sw_score_pct(f.score_raw), chip.ram_version);
			return SW_EXIT_OK;
		}
		if (cs.status == 3 || f.cal_status != 3)
			break;
		if (env->now_ms(env->clk) - start >= RESTORE_SETTLE_MS)
			return sw_err_set(e, SW_EXIT_CAL,
					  "%s: wrote %s but calibration_status is %d, not 3",
					  b->name, path, cs.status);
		env->sleep_ms(env->clk, RESTORE_POLL_MS);
	}
	sw_note(env, "restored %s calibration from %s: status %d, score %.3f%% (saved with status %d, %.3f%%)",
		b->name, path, cs.status, sw_score_pct(cs.score_raw),
		f.cal_status, sw_score_pct(f.score_raw));
	return SW_EXIT_OK;
}

void sw_json_str(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		unsigned char c = (unsigned char)*s;

		if (c == '"' || c == '\\')
			fprintf(f, "\\%c", c);
		else if (c < 0x20)
			fprintf(f, "\\u%04x", c);
		else
			fputc(c, f);
	}
	fputc('"', f);
}

/* How status names and shows each feature sensor. */
static const struct {
	const char *name;
	const char *unit;	/* ASCII: "C", not a degree sign */
	int decimals;		/* the firmware's resolution: 0.01 hPa, C, % */
} feature_kinds[SW_NFEATURES] = {
	[SW_FEATURE_PRESSURE] = { "pressure", "kPa", 3 },
	[SW_FEATURE_HUMIDITY] = { "humidity", "%", 2 },
	[SW_FEATURE_TEMP] = { "temperature", "C", 2 },
};

/* "firmware:" and "feature sensors:" lines; hi NULL: not read (why). */
static void status_hub_text(FILE *out, const struct sw_hub_info *hi,
			    const char *why)
{
	static const char *const source[] = {
		[SW_FW_EEPROM] = "from the board's EEPROM",
		[SW_FW_HOST] = "uploaded by the host",
	};
	unsigned int i;

	if (!hi) {
		fprintf(out, "firmware:            unknown (%s)\n", why);
		fprintf(out, "feature sensors:     unknown (%s)\n", why);
		return;
	}
	if (hi->fw_source == SW_FW_UNKNOWN)
		fprintf(out, "firmware:            unknown (%s)\n", hi->fw_why);
	else
		fprintf(out, "firmware:            %s\n", source[hi->fw_source]);
	if (!hi->nfeatures)
		fprintf(out, "feature sensors:     none\n");
	for (i = 0; i < hi->nfeatures; i++) {
		const struct sw_feature *f = &hi->features[i];

		fprintf(out, "%-21s%s ", i ? "" : "feature sensors:",
			feature_kinds[f->kind].name);
		if (f->have_value)
			fprintf(out, "%.*f %s", feature_kinds[f->kind].decimals,
				f->value, feature_kinds[f->kind].unit);
		else
			fprintf(out, "(no value while a buffer streams)");
		fprintf(out, " at %d Hz\n", f->rate_hz);
	}
}

/* "firmware_source" and "feature_sensors" members; null when unknown. */
static void status_hub_json(FILE *out, const struct sw_hub_info *hi)
{
	static const char *const source[] = {
		[SW_FW_UNKNOWN] = "null",
		[SW_FW_EEPROM] = "\"eeprom\"",
		[SW_FW_HOST] = "\"host\"",
	};
	unsigned int i;

	if (!hi) {
		fprintf(out, ",\"firmware_source\":null,\"feature_sensors\":null");
		return;
	}
	fprintf(out, ",\"firmware_source\":%s,\"feature_sensors\":[",
		source[hi->fw_source]);
	for (i = 0; i < hi->nfeatures; i++) {
		const struct sw_feature *f = &hi->features[i];

		fprintf(out, "%s{\"name\":\"%s\",\"value\":", i ? "," : "",
			feature_kinds[f->kind].name);
		if (f->have_value)
			fprintf(out, "%.*f", feature_kinds[f->kind].decimals,
				f->value);
		else
			fprintf(out, "null");
		fprintf(out, ",\"unit\":\"%s\",\"rate_hz\":%d}",
			feature_kinds[f->kind].unit, f->rate_hz);
	}
	fprintf(out, "]");
}

int sw_cmd_status(struct sw_backend *b, const struct sw_opts *o,
		  struct sw_env *env, struct sw_err *e)
{
	struct sw_chip_info chip;
	struct sw_cal_state cs;
	struct sw_hub_info hub;
	struct sw_err cerr, ferr, herr;
	struct sw_file f;
	char path[4096], old[4096], why[4400], when[40];
	bool have_chip, have_file, have_hub;
	FILE *out = env->out;
	int ret, err = 0;

	ret = b->ops->cal_state(b, &cs, e);
	if (ret)
		return ret;
	sw_err_clear(&cerr);
	have_chip = b->ops->chip_info(b, &chip, &cerr) == SW_EXIT_OK;
	sw_err_clear(&herr);
	have_hub = b->ops->hub_info(b, &hub, &herr) == SW_EXIT_OK;
	sw_file_path(o, b, path, sizeof(path));
	sw_err_clear(&ferr);
	ret = load_existing(o, path, have_chip ? &chip : NULL, &f, &have_file,
			    why, sizeof(why), &err, &ferr);
	/*
	 * The chip's attributes are world-readable, the state directory is
	 * root's: a user still sees the chip's part. Root is told of a state
	 * file it must not trust (exit status).
	 */
	if (ret && geteuid() != 0 &&
	    (ret == SW_EXIT_PERM || err == EACCES)) {
		snprintf(why, sizeof(why), "needs root to read (%s)", ferr.msg);
		ret = SW_EXIT_OK;
	}
	if (ret == SW_EXIT_STATEDIR) {
		snprintf(why, sizeof(why), "%s", ferr.msg);
		ret = SW_EXIT_OK;
	}
	if (ret)
		return sw_err_set(e, ret, "%s", ferr.msg);
	if (!have_file && !why[0] && !o->file &&
	    (legacy_path(o, b, 0, old, sizeof(old)) ||
	     legacy_path(o, b, 1, old, sizeof(old))))
		snprintf(why, sizeof(why),
			 "none yet; %s (saved under an older key) moves here at the next restore or save",
			 old);
	if (!have_file && !why[0])
		snprintf(why, sizeof(why), "no saved calibration yet");
	if (have_file)
		fmt_time(f.saved_at, when, sizeof(when));

	if (o->json) {
		fprintf(out, "{\"device\":");
		sw_json_str(out, b->name);
		fprintf(out, ",\"backend\":\"%s\",\"key\":", b->kind);
		sw_json_str(out, b->key);
		if (have_chip)
			fprintf(out, ",\"product_id\":%u,\"revision_id\":%u,\"rom_version\":%u,\"ram_version\":%u",
				chip.product_id, chip.revision_id,
				chip.rom_version, chip.ram_version);
		status_hub_json(out, have_hub ? &hub : NULL);
		if (cs.reported)
			fprintf(out, ",\"calibration_status\":%d,\"calibration_score\":%.3f,\"calibration_score_raw\":%u,\"mag_transient\":%d,\"gyro_bias_update\":%d,\"mag_calibration_update\":%d,\"file\":",
				cs.status, sw_score_pct(cs.score_raw),
				cs.score_raw, cs.mag_transient,
				cs.gyro_bias_update, cs.mag_cal_update);
		else
			fprintf(out, ",\"calibration_status\":null,\"calibration_score\":null,\"calibration_score_raw\":null,\"mag_transient\":null,\"gyro_bias_update\":null,\"mag_calibration_update\":null,\"file\":");
		sw_json_str(out, path);
		if (have_file)
			fprintf(out, ",\"saved\":{\"calibration_status\":%d,\"calibration_score\":%.3f,\"calibration_score_raw\":%u,\"saved_at\":%llu}}\n",
				f.cal_status, sw_score_pct(f.score_raw),
				f.score_raw, (unsigned long long)f.saved_at);
		else {
			fprintf(out, ",\"saved\":null,\"saved_problem\":");
			sw_json_str(out, why);
			fprintf(out, "}\n");
		}
		return SW_EXIT_OK;
	}

	fprintf(out, "device:              %s (%s backend)\n", b->name, b->kind);
	fprintf(out, "key:                 %s\n", b->key);
	if (have_chip)
		fprintf(out, "chip:                ProductID 0x%02x, RevisionID 0x%02x, ROM 0x%04x, RAM 0x%04x\n",
			chip.product_id, chip.revision_id, chip.rom_version,
			chip.ram_version);
	else
		fprintf(out, "chip:                unknown (%s)\n", cerr.msg);
	status_hub_text(out, have_hub ? &hub : NULL, herr.msg);
	if (!cs.reported) {
		if (have_chip)
			fprintf(out, "calibration status:  not reported by this firmware (RAM 0x%04x)\n",
				chip.ram_version);
		else
			fprintf(out, "calibration status:  not reported by this firmware\n");
	} else {
		fprintf(out, "calibration status:  %d%s\n", cs.status,
			cs.status == 3 ? " (complete)" : "");
		fprintf(out, "calibration score:   %.3f%%\n",
			sw_score_pct(cs.score_raw));
		fprintf(out, "mag transient:       %d\n", cs.mag_transient);
		fprintf(out, "gyro bias update:    %d\n", cs.gyro_bias_update);
		fprintf(out, "mag cal update:      %d\n", cs.mag_cal_update);
	}
	if (have_file)
		fprintf(out, "saved file:          %s (status %d, score %.3f%%, saved %s)\n",
			path, f.cal_status, sw_score_pct(f.score_raw), when);
	else
		fprintf(out, "saved file:          %s: %s\n", path, why);
	return SW_EXIT_OK;
}

int sw_cmd_key(struct sw_backend *b, const struct sw_opts *o,
	       struct sw_env *env, struct sw_err *e)
{
	char unit[SW_KEY_MAX * 4];

	if (!o->udev) {
		fprintf(env->out, "%s\n", b->key);
		return SW_EXIT_OK;
	}
	if (!sw_key_unit_escape(b->key, unit, sizeof(unit)) ||
	    strlen(unit) > 255 - strlen("sentral-warmstart-restore@.service"))
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: key %s is too long for a systemd unit name",
				  b->name, b->key);
	fprintf(env->out, "SENTRAL_WARMSTART_KEY=%s\nSENTRAL_WARMSTART_UNIT=%s\n",
		b->key, unit);
	return SW_EXIT_OK;
}

int sw_cmd_show(const struct sw_opts *o, struct sw_env *env,
		struct sw_err *e)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	enum sw_file_check c;
	char detail[160], when[40];
	struct sw_file f;
	FILE *out = env->out;
	size_t len;
	int n;

	/* Only reading: following a symlink the user named is harmless. */
	if (sw_file_read(o->file, SW_READ_ANY, buf, &len, NULL, e))
		return e->code;
	c = sw_file_decode(buf, len, &f, detail, sizeof(detail));
	if (c != SW_CHECK_OK)
		return sw_err_set(e, SW_EXIT_FILE, "%s: refused: %s (%s)",
				  o->file, sw_check_name(c), detail);
	fmt_time(f.saved_at, when, sizeof(when));
	fprintf(out, "file:                %s\n", o->file);
	fprintf(out, "format:              %s version %d, %zu bytes, CRC-32 0x%08x ok\n",
		SW_FILE_MAGIC, SW_FILE_VERSION, len,
		sw_get_le32(buf + SW_FILE_SIZE - 4));
	fprintf(out, "ProductID:           0x%02x\n", f.chip.product_id);
	fprintf(out, "RevisionID:          0x%02x\n", f.chip.revision_id);
	fprintf(out, "ROM version:         0x%04x\n", f.chip.rom_version);
	fprintf(out, "RAM version:         0x%04x\n", f.chip.ram_version);
	fprintf(out, "calibration status:  %d\n", f.cal_status);
	fprintf(out, "calibration score:   %.3f%% (raw 0x%04x)\n",
		sw_score_pct(f.score_raw), f.score_raw);
	fprintf(out, "saved at:            %s (%llu)\n", when,
		(unsigned long long)f.saved_at);
	fprintf(out, "parameters:\n");
	for (n = 1; n <= SW_NPARAMS; n++) {
		uint32_t raw = sw_get_le32(f.payload + 4 * (n - 1));

		fprintf(out, "  %2d  %-11s 0x%08x  %.7g", n, sw_param_name(n),
			raw, (double)sw_blob_param(f.payload, n));
		if (n >= SW_PARAM_ACCEL_X && n < SW_PARAM_ACCEL_X + 3)
			fprintf(out, " g (accel %c offset, %d LSB)",
				'X' + n - SW_PARAM_ACCEL_X,
				sw_g_to_lsb(sw_blob_param(f.payload, n)));
		fputc('\n', out);
	}
	return SW_EXIT_OK;
}
