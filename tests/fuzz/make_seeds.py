#!/usr/bin/env python3
"""Writes the hand-made seed inputs of tests/fuzz/corpus/ (protocol frames, vehicle frame/tick
sequences, a motion-capture CSV) and copies the shipped YAML files. The adaptation store's seeds
come from the store itself (tests/fuzz/make_store_seeds.cpp). Run from the repository root;
the output is checked in, so run it again only when the formats change."""
import math
import os
import shutil
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join(ROOT, "tests", "fuzz", "corpus")
TOKEN = 0x4242
NODE = 1
BROADCAST = 15


def ident(type_, node):
    return (type_ << 4) | node


def frame(type_, node, payload):
    return ident(type_, node), payload


def kill(node=NODE, reason=0):
    return frame(0x01, node, struct.pack("<HB", TOKEN, reason))


def command(code, seq, arg=0, node=NODE, token=TOKEN):
    return frame(0x02, node, struct.pack("<BBHi", code, seq, token, arg))


def rate_thrust(thrust_mps2, seq, rates=(0, 0, 0), node=NODE):
    r = [int(round(x / 0.002)) for x in rates]
    return frame(0x03, node, struct.pack("<hhhH", *r, int(round(thrust_mps2 / 0.01)) | ((seq & 15) << 12)))


def gs_heartbeat(seq, time_ms=0, token=TOKEN, node=BROADCAST):
    return frame(0x0A, node, struct.pack("<IHBB", time_ms, token, 1, seq & 0xFF))


def battery(mv, node=NODE):
    return frame(0x16, node, struct.pack("<H", mv))


def write(folder, name, data):
    os.makedirs(os.path.join(CORPUS, folder), exist_ok=True)
    with open(os.path.join(CORPUS, folder, name), "wb") as f:
        f.write(data)


def protocol_seeds():
    frames = {
        "kill": kill(),
        "command_arm": command(1, 7),
        "command_expect_catch": command(4, 8, 1500),
        "rate_thrust": rate_thrust(9.81, 3, (0.5, -0.25, 0.1)),
        "gs_heartbeat": gs_heartbeat(9, 12345),
        "hil_imu_gyro": frame(0x04, NODE, struct.pack("<hhhH", 10, -20, 30, 77)),
        "hil_imu_accel": frame(0x05, NODE, struct.pack("<hhhH", 0, 0, 1962, 77)),
        "hil_motors": frame(0x06, NODE, bytes([0xFF, 0x0F, 0x80, 0x00, 0x08, 0x40, 77, 0])),
        "impact": frame(0x08, NODE, struct.pack("<IHBB", 1000000, 4500, 0x81, 2)),
        "command_ack": frame(0x09, NODE, bytes([7, 1, 0, 1, 0])),
        "vehicle_heartbeat": frame(0x0B, NODE, struct.pack("<IBBBB", 5000, 2, 0x0F, 0x13, 0)),
        "timesync_request": frame(0x0C, NODE, struct.pack("<IB", 123456, 4)),
        "timesync_reply": frame(0x0D, NODE, struct.pack("<II", 123456, 654321)),
        "telemetry_rates": frame(0x10, NODE, struct.pack("<hhhH", 1, 2, 3, 981 | (5 << 12))),
        "telemetry_attitude": frame(0x11, NODE, struct.pack("<hhhh", 32767, 0, 0, 0)),
        "telemetry_motors": frame(0x12, NODE, struct.pack("<HHHH", 30000, 31000, 32000, 33000)),
        "telemetry_status": frame(0x13, NODE, struct.pack("<HHHBB", 250, 16000, 3, 0, 1)),
        "hil_battery": frame(0x16, NODE, struct.pack("<H", 11400)),
    }
    for name, (i, payload) in frames.items():
        write("protocol", name, struct.pack("<H", i) + payload)


# vehicle_fuzz.cpp's 12-byte records.
def rec_frame(f):
    i, payload = f
    return bytes([0]) + struct.pack("<HB", i, len(payload)) + payload.ljust(8, b"\0")


def rec_tick(dt_quarter_ms=4, gyro=(0, 0, 0), accel=(0, 0, 0), flags=0):
    return bytes([0x80 | flags, dt_quarter_ms]) + struct.pack("<6b", *gyro, *accel) + b"\0" * 4


class Script:
    def __init__(self):
        self.data = b""
        self.hb = 0
        self.sp = 0
        self.cmd = 0

    def tick(self, n=1, heartbeat=True, thrust=None, **kw):
        for _ in range(n):
            if heartbeat:
                self.hb += 1
                self.data += rec_frame(gs_heartbeat(self.hb))
            if thrust is not None:
                self.sp = (self.sp + 1) & 15
                self.data += rec_frame(rate_thrust(thrust, self.sp))
            self.data += rec_tick(**kw)
        return self

    def frame(self, f):
        self.data += rec_frame(f)
        return self

    def command(self, code, arg=0):
        self.cmd += 1
        return self.frame(command(code, self.cmd & 0xFF, arg))


def vehicle_seeds():
    write("vehicle", "idle_ticks", Script().tick(5, heartbeat=False).data)
    write("vehicle", "arm", Script().tick(3).command(1).tick(3).data)
    write("vehicle", "arm_fly_kill", Script().tick(3).command(1).tick(2).tick(5, thrust=9.81).frame(kill()).tick(2).data)
    write("vehicle", "arm_fly_land", Script().tick(3).command(1).tick(2).tick(5, thrust=9.81).command(3).tick(5).data)
    write("vehicle", "fly_link_lost", Script().tick(3).command(1).tick(2).tick(3, thrust=9.81).tick(30, heartbeat=False).data)
    write("vehicle", "kill_disarm_rearm", Script().tick(3).command(1).tick(2).frame(kill(BROADCAST)).tick(1).command(2).tick(1).command(1).tick(2).data)
    write("vehicle", "expect_catch_impact",
          Script().tick(3).command(1).tick(2).tick(5, thrust=9.81).command(4, 500).tick(1, thrust=9.81)
          .tick(3, thrust=9.81, accel=(0, 0, 120)).tick(3, thrust=9.81).command(5).tick(2, thrust=9.81).data)
    # The pack sagging in flight, then readings out of range (a 2S pack, none) and silence.
    sag = Script().tick(3).command(1).tick(2)
    for mv in (12600, 12100, 11600, 11100, 7000, 0, 65535, 11000):
        sag.frame(battery(mv)).tick(10, thrust=9.81)
    write("vehicle", "battery_sag", sag.tick(20, thrust=9.81).data)
    write("vehicle", "imu_unhealthy", Script().tick(3).command(1).tick(2).tick(10, thrust=9.81, flags=0x40).data)


def mocap_seed():
    lines = ["t,body,x,y,z,qw,qx,qy,qz"]
    # Vehicles hover, the pole flies ballistically from vehicle 1 towards vehicle 2 (200 Hz).
    for k in range(12):
        t = 0.005 * k
        lines.append(f"{t:.3f},vehicle1,0.000,0.000,1.000,1.000000,0.000000,0.000000,0.000000")
        lines.append(f"{t:.3f},vehicle2,2.000,0.000,1.300,1.000000,0.000000,0.000000,0.000000")
        z = 1.8 + 5.5 * t - 0.5 * 9.81 * t * t
        a = 0.3 + 2.5 * t
        lines.append(f"{t:.3f},pole,{0.3 + 1.5 * t:.4f},0.0000,{z:.4f},"
                     f"{math.cos(a / 2):.6f},0.000000,{math.sin(a / 2):.6f},0.000000")
    write("mocap", "free_flight.csv", ("\n".join(lines) + "\n").encode())
    shutil.copy(os.path.join(ROOT, "tests", "data", "malformed_mocap.csv"), os.path.join(CORPUS, "mocap", "malformed_mocap.csv"))


def yaml_seeds():
    os.makedirs(os.path.join(CORPUS, "yaml_config"), exist_ok=True)
    sources = ["hil/config/plant.yaml", "groundstation/config/vehicle_limits.yaml"] + [
        "hil/config/scenarios/" + n for n in sorted(os.listdir(os.path.join(ROOT, "hil/config/scenarios")))]
    # Without the .yaml extension: tests/repository would read a seed's comments as the
    # repository's own and find its relative references (../plant.yaml) broken.
    for s in sources:
        name = os.path.basename(s).replace(".yaml", "")
        shutil.copy(os.path.join(ROOT, s), os.path.join(CORPUS, "yaml_config", name))


protocol_seeds()
vehicle_seeds()
mocap_seed()
yaml_seeds()
