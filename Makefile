# SPDX-License-Identifier: GPL-2.0-only
#
# sentral: driver, tool and tests for the PNI SENtral / EM7180 sensor hub.
#
#   make              build the driver against KDIR and the tool
#   make check        run every test on the simulated chip (every kernel)
#   make check-long   the suites too long for make check (tests/long-suites)
#   make demo         the whole story on the simulated chip
#   make bench        measure bus use, timing and streaming on the simulated chip
#   make fuzz         fuzz the tool's file parser and command line (long run)
#   make uml          build the User-Mode Linux test kernels
#   make cross        build the driver for arm64, armhf, i386 and with clang
#   make upstream     write the mainline patch series into build/upstream/
#   make overlay      build the Raspberry Pi devicetree overlay
#   make install      install the modules, the tool, its udev rule and unit,
#                     and the overlay
#   make deb          Debian packages sentral-warmstart and em7180-dkms in build/deb/
#                     (DEB_ARCH=arm64: cross-built, in build/deb-arm64/)
#   make dist         the release tarball build/sentral-VERSION.tar.gz of the
#                     committed tree (HEAD); it builds the .debs without git
#   make release      build/release/: the tarball, the .debs for amd64, arm64
#                     and armhf built from it, SHA256SUMS
#   make system-check install the packages in a Debian image, boot it under QEMU

KDIR     ?= /lib/modules/$(shell uname -r)/build
# Test kernels: each version, and 6.12 with the sanitisers (tests/uml/config-san)
VERSIONS ?= 7.2 6.12 6.1 6.12-san
TOOL     := tools/sentral-warmstart

all: modules tool

modules:
	@test -d "$(KDIR)" || { echo "KDIR=$(KDIR) not found: install the kernel headers or set KDIR"; exit 1; }
	$(MAKE) -C $(KDIR) M=$(CURDIR) CONFIG_EM7180=m CONFIG_EM7180_I2C=m modules

modules_install: modules
	$(MAKE) -C $(KDIR) M=$(CURDIR) CONFIG_EM7180=m CONFIG_EM7180_I2C=m modules_install

# The project's own builds fail on any warning (WERROR=1); a distribution's
# package build (debian/rules) does not force it.
tool:
	$(MAKE) -C $(TOOL) WERROR=1

prepare:
	tests/kernel/prepare $(VERSIONS)

uml: prepare
	@for v in $(VERSIONS); do tests/uml/build $$v || exit 1; done

# kunit.py builds its own kernel per version; flavours run the suite in UML
# (as make check does for every kernel, tests/kernel/kunit-uml).
kunit: prepare
	@for v in $(VERSIONS); do \
		case $$v in \
		*-*) tests/kernel/kunit-uml $$v ;; \
		*) tests/kernel/kunit $$v ;; \
		esac || exit 1; \
	done

# Only the test kernels that a selected suite boots are built: make check
# leaves 6.12-san to make check-long (tests/long-suites), and 6.12 is built
# for its lint and KUnit suites.
check: prepare tool
	@for v in $$(VERSIONS="$(VERSIONS)" tests/run-suites --list | sed -n 's|/.*||p' | sort -u); do \
		tests/uml/build $$v || exit 1; \
	done
	VERSIONS="$(VERSIONS)" tests/run-suites

check-long: prepare tool
	@for v in $$(VERSIONS="$(VERSIONS)" LONG=1 tests/run-suites --list | sed -n 's|/.*||p' | sort -u); do \
		tests/uml/build $$v || exit 1; \
	done
	VERSIONS="$(VERSIONS)" LONG=1 tests/run-suites

# The demo boots the primary kernel only.
demo: VERSIONS = 7.2
demo: uml tool
	tests/demo

# Figures against DESIGN §6 on the primary kernel (build/bench.json).
bench: VERSIONS = 7.2
bench: uml tool
	tests/bench/bench

fuzz:
	$(MAKE) -C $(TOOL) WERROR=1 fuzz

# W=1 builds of the driver and the simulator for each architecture a user
# may have, on each kernel of the matrix (tests/kernel/cross).  The .deb cross-builds
# join them once debian/ exists.
cross:
	@status=0; for v in 7.2 6.12 6.1; do \
		tests/kernel/cross $$v arm64 armhf i386 clang || status=1; \
	done; \
	if [ -d debian ]; then tests/kernel/cross-deb arm64 armhf || status=1; \
	else echo "make cross: no debian/ in this tree, no .deb cross-builds"; fi; \
	exit $$status

upstream:
	scripts/upstream-series

overlay:
	$(MAKE) -C boards/raspberrypi

# Built from a copy of the source files (tracked or new, not ignored), so
# that the checkout stays clean: the source package (.dsc, .tar.xz) and the
# .debs; lintian must find nothing down to its pedantic tags, or an
# override in debian/ that says why. DEB_ARCH=arm64: the .debs alone,
# cross-built for that architecture into build/deb-arm64/
# (tests/kernel/cross-deb installs what that needs). DEB_TARBALL=FILE:
# built from that release tarball (make dist) instead (make release).
DEB_OUT = build/deb$(if $(DEB_ARCH),-$(DEB_ARCH))
deb:
	tests/system/prepare --deb
	rm -rf $(DEB_OUT) && mkdir -p $(DEB_OUT)/src
ifeq (,$(DEB_TARBALL))
	git ls-files -z --cached --others --exclude-standard | \
		tar -c --null -T - --ignore-failed-read | tar -x -C $(DEB_OUT)/src
else
	tar -xzf $(DEB_TARBALL) -C $(DEB_OUT)/src --strip-components=1
endif
	cd $(DEB_OUT)/src && dpkg-buildpackage $(if $(DEB_ARCH),-a $(DEB_ARCH) -Pcross -b,-F) -us -uc
	lintian --pedantic -I --fail-on error,warning,info,pedantic $(DEB_OUT)/*.changes

# The release tarball: the committed tree (HEAD, not uncommitted changes)
# under sentral-VERSION/, VERSION the newest entry of debian/changelog.
# Nothing in its build needs git: unpacked anywhere, `dpkg-buildpackage
# -us -uc -b` in it builds the .debs (tests/kernel/dist checks it).
DIST_VERSION = $(shell git show HEAD:debian/changelog 2>/dev/null | \
	sed -n '1s/^[^(]*(\([^)]*\)).*/\1/p')
dist:
	@test -n "$(DIST_VERSION)" || { echo "make dist: no version in debian/changelog"; exit 1; }
	@git diff --quiet HEAD -- 2>/dev/null || \
		echo "make dist: uncommitted changes are not in the tarball (it is HEAD)"
	mkdir -p build
	git archive --format=tar.gz --prefix=sentral-$(DIST_VERSION)/ \
		-o build/sentral-$(DIST_VERSION).tar.gz HEAD
	@echo "build/sentral-$(DIST_VERSION).tar.gz"

# The release, HEAD's: into RELEASE_DIR (build/release/) the tarball of
# make dist, the packages built from it (make deb DEB_TARBALL=: amd64, with
# lintian) and cross-built for RELEASE_ARCHES (tests/kernel/cross-deb, as
# make cross does: arm64 and armhf, with the overlay), without the debug
# symbols' packages, and SHA256SUMS of them all. Any architecture missing
# fails it (cross-deb skips one whose index the mirror serves incomplete).
RELEASE_DIR ?= build/release
RELEASE_ARCHES ?= arm64 armhf
HOST_ARCH = $(shell dpkg --print-architecture)
release: dist
	@git diff --quiet HEAD -- && test -z "$$(git ls-files --others --exclude-standard)" || \
		echo "make release: uncommitted changes are not in the release (it is HEAD)"
	rm -rf $(RELEASE_DIR) && mkdir -p $(RELEASE_DIR)
	$(MAKE) deb DEB_TARBALL=$(CURDIR)/build/sentral-$(DIST_VERSION).tar.gz
	$(if $(filter-out $(HOST_ARCH),$(RELEASE_ARCHES)),DEB_TARBALL=$(CURDIR)/build/sentral-$(DIST_VERSION).tar.gz \
		tests/kernel/cross-deb $(filter-out $(HOST_ARCH),$(RELEASE_ARCHES)))
	cp build/sentral-$(DIST_VERSION).tar.gz build/deb/em7180-dkms_$(DIST_VERSION)_all.deb \
		build/deb/sentral-warmstart_$(DIST_VERSION)_$(HOST_ARCH).deb $(RELEASE_DIR)/
	cp build/deb/em7180-overlay_$(DIST_VERSION)_$(HOST_ARCH).deb $(RELEASE_DIR)/ 2>/dev/null || true
	@for a in $(filter-out $(HOST_ARCH),$(RELEASE_ARCHES)); do \
		cp build/deb-$$a/sentral-warmstart_$(DIST_VERSION)_$$a.deb \
			build/deb-$$a/em7180-overlay_$(DIST_VERSION)_$$a.deb $(RELEASE_DIR)/ || \
			{ echo "make release: no $$a packages (build/deb-$$a.log)"; exit 1; }; \
	done
	cd $(RELEASE_DIR) && sha256sum -- * >SHA256SUMS
	@echo "$(RELEASE_DIR):" && ls $(RELEASE_DIR)

# The packages installed in a Debian 12 image and booted under QEMU with
# systemd on the stock 6.1 and 6.12 kernels (builds the packages itself);
# RELEASE=trixie: a Debian 13 image, its stock 6.12 and 7.2 from backports.
system-check:
	tests/system/run $(RELEASE)

install: modules_install
	$(MAKE) -C $(TOOL) install
	$(MAKE) -C boards/raspberrypi install

clean:
	-test -d "$(KDIR)" && $(MAKE) -C $(KDIR) M=$(CURDIR) clean
	-$(MAKE) -C $(TOOL) clean
	-$(MAKE) -C boards/raspberrypi clean

distclean: clean
	rm -rf build

.PHONY: all modules modules_install tool prepare uml kunit check check-long demo bench fuzz \
	cross upstream overlay deb dist release system-check install clean distclean
