# The front door (as PX4 does): wraps the CMake presets for people who just want to build,
# try and test. `make demo` and `make test` install what is missing on Debian 12 first.
.PHONY: all deps host host-sanitize firmware cortex-m4 stm32f405 demo test test-host test-sanitize \
        test-firmware test-fuzz fuzz-build fuzz hil pil bench flash clean help

JOBS ?= $(shell nproc)
# make flash: the HIL image; make flash BOARD=omnibusf4: the flight image (DShot600);
# BOARD=omnibusf4-pwm: the flight image with PWM motor output (scripts/flash.sh). KEY=FILE: the
# vehicle's link key (docs/security.md), required.
BOARD ?=
FUZZ_SECONDS ?= 600
PIL_SEED ?= 1

all: host firmware

help:
	@echo "make demo       install what is missing, build, fly the firmware self-test (host and Cortex-M4 in QEMU)"
	@echo "make test       install what is missing, build every preset, run every test"
	@echo "make hil        run the HIL tests on virtual CAN (fw_vehicle on SocketCAN, in a QEMU guest; docs/hil.md)"
	@echo "make pil        fly the paper's series on the Cortex-M4 image in QEMU and compare it with the host's core (PIL_SEED, default 1)"
	@echo "make bench      run the benchmarks (bench_firmware, bench_planning, ...)"
	@echo "make fuzz       run every libFuzzer target FUZZ_SECONDS (default 600) on its corpus (tests/fuzz)"
	@echo "make firmware   build the Cortex-M4 images (mps2-an386, the stm32f405 HIL and flight images)"
	@echo "make flash      KEY=FILE: program the STM32F405 HIL image with openocd, keyed; BOARD=omnibusf4: the flight image with dfu-util"
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

# The libFuzzer targets (clang; tests/fuzz/CMakeLists.txt builds only what they need).
fuzz-build: deps
	cmake --preset fuzz >/dev/null
	cmake --build --preset fuzz -j $(JOBS)

demo: host firmware
	@scripts/demo.sh

test-host: host
	ctest --preset host

# The HIL tests on virtual CAN (label hil; make test-host runs them too): the real fw_vehicle on
# SocketCAN, in a QEMU guest with Debian's kernel (scripts/hil-vm.sh, docs/hil.md).
hil: host
	ctest --preset host -L hil

# Processor in the loop: the paper's series on the Cortex-M4 image in QEMU, one per vehicle,
# against the same series on the host's core (scripts/pil.sh, docs/hil.md); some minutes.
pil: host cortex-m4
	@scripts/pil.sh build/host/hil/hil build/cortex-m4/firmware/ports/mps2_an386/fw_mps2_an386_pil.elf build/pil $(PIL_SEED)

test-sanitize: host-sanitize
	ctest --preset host-sanitize

test-firmware: firmware
	ctest --preset cortex-m4
	ctest --preset stm32f405

# Each fuzz target replays its checked-in corpus and mutates for a few seconds (label fuzz).
test-fuzz: fuzz-build
	ctest --preset fuzz

fuzz: fuzz-build
	FUZZ_SECONDS=$(FUZZ_SECONDS) scripts/fuzz.sh

test: demo test-host test-sanitize test-firmware test-fuzz
	@echo "make test: every preset built and every test passed"

bench: host
	@for b in build/host/tests/bench/bench_*; do echo "== $$b"; $$b --benchmark_counters_tabular=true || exit 1; done

flash: stm32f405
	@KEY="$(KEY)" scripts/flash.sh "$(BOARD)"

clean:
	rm -rf build
