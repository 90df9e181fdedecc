# The front door (as PX4 does): wraps the CMake presets for people who just want to build,
# try and test. `make demo` and `make test` install what is missing on Debian 12 first.
.PHONY: all deps host host-sanitize firmware cortex-m4 stm32f405 demo test test-host test-sanitize \
        test-firmware bench flash clean help

JOBS ?= $(shell nproc)
# make flash: the HIL image; make flash BOARD=omnibusf4: the flight image (DShot600);
# BOARD=omnibusf4-pwm: the flight image with PWM motor output (scripts/flash.sh).
BOARD ?=

all: host firmware

help:
	@echo "make demo       install what is missing, build, fly the firmware self-test (host and Cortex-M4 in QEMU)"
	@echo "make test       install what is missing, build every preset, run every test"
	@echo "make bench      run the benchmarks (bench_firmware, bench_planning, ...)"
	@echo "make firmware   build the Cortex-M4 images (mps2-an386, the stm32f405 HIL and flight images)"
	@echo "make flash      program the STM32F405 HIL image with openocd; BOARD=omnibusf4: the flight image with dfu-util"
	@echo "                (see firmware/ports/stm32f405/README.md)"

deps:
	@scripts/install-deps.sh

host: deps
	cmake --preset host >/dev/null
	cmake --build --preset host -j $(JOBS)

host-sanitize: deps
	cmake --preset host-sanitize >/dev/null
	cmake --build --preset host-sanitize -j $(JOBS)

cortex-m4: deps
	cmake --preset cortex-m4 >/dev/null
	cmake --build --preset cortex-m4 -j $(JOBS)

stm32f405: deps
	cmake --preset stm32f405 >/dev/null
	cmake --build --preset stm32f405 -j $(JOBS)

firmware: cortex-m4 stm32f405

demo: host firmware
	@scripts/demo.sh

test-host: host
	ctest --preset host

test-sanitize: host-sanitize
	ctest --preset host-sanitize

test-firmware: firmware
	ctest --preset cortex-m4
	ctest --preset stm32f405

test: demo test-host test-sanitize test-firmware
	@echo "make test: every preset built and every test passed"

bench: host
	@for b in build/host/tests/bench/bench_*; do echo "== $$b"; $$b --benchmark_counters_tabular=true || exit 1; done

flash: stm32f405
	@scripts/flash.sh "$(BOARD)"

clean:
	rm -rf build
