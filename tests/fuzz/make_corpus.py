#!/usr/bin/env python3
"""Writes the seed corpus of pbf_fuzz_c_api (tests/fuzz/corpus/*.bin).

Each seed is a short, valid call sequence in the byte encoding that fuzz_c_api.cpp decodes
(one opcode byte, then that call's argument bytes); the fuzzer mutates from there. Run it
again after changing the decoder:  python3 tests/fuzz/make_corpus.py
"""
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")

# opcodes (op % 20 in LLVMFuzzerTestOneInput)
CREATE, DESTROY, STEP, PARAMS, GET, GRAVITY, EMIT, NEW_EMITTER, DEL_EMITTER, EMITTER_UPDATE, \
    NEW_COLLIDER, DEL_COLLIDER, POSE, COPY, MAP = 0, 2, 3, 6, 7, 8, 9, 11, 12, 13, 14, 15, 16, 17, 18


def u16(v):
    return struct.pack("<H", v)


def frac(x):
    """A Reader::f value at fraction x of its [lo, hi] range."""
    return bytes([0]) + u16(int(round(x * 65535)))


def special(k):
    """A Reader::f special value (index into kSpecialFloats: 16 Inf, 18 NaN, 14 FLT_MAX)."""
    return bytes([200, k])


def raw_f(v):
    return bytes([250]) + struct.pack("<f", v)


W0 = bytes([0])          # pick_world: live world 0
STALE = bytes([11])      # pick_world: a destroyed world
FORGED = bytes([15]) + struct.pack("<II", 3, 7)


def create(mask=0, extra=b""):
    return bytes([CREATE]) + u16(mask) + extra


def emit(lo=(0.2, 0.0, 0.2), size=(1.0, 1.0, 1.0), ptrs=0x28):
    b = bytes([EMIT]) + W0 + bytes([0])
    for a in range(3):
        b += frac(lo[a] / 0.9) + frac(size[a])
    return b + bytes([255]) + bytes([0]) + bytes([ptrs])


def step(dt_frac=1 / 3, world=W0):
    return bytes([STEP]) + world + frac(dt_frac)


def copy(which, max_mode=1):
    return bytes([COPY]) + W0 + bytes([which, max_mode, 0x20])


seeds = {}

# 1. a block of water: emit, step, copy everything out, map, read, unmap, destroy.
seeds["block_map.bin"] = (create() + emit() + step() + step() + step() + copy(0) + copy(1) + copy(2) +
                          copy(0, 5) + bytes([MAP]) + W0 + bytes([0, 0, 0x80]) + bytes([MAP]) + W0 + bytes([2]) +
                          bytes([MAP]) + W0 + bytes([1]) + bytes([DESTROY]) + W0)

# 2. nozzle + drain: the accounting emitted - drained == count over steps.
nozzle = (bytes([NEW_EMITTER]) + W0 + bytes([0]) + u16(0) +
          frac(0.5) + frac(0.5) + frac(0.0) + frac(0.9) + frac(0.5) + frac(0.0) + frac(0.5) + frac(0.5) + frac(0.0) +
          frac(0.5) + frac(0.3) + frac(0.5) + bytes([0x80]))
drain = (bytes([NEW_EMITTER]) + W0 + bytes([8]) + u16(0) +
         frac(0.5) + frac(0.0) + frac(0.2) + frac(0.5) + frac(0.0) + frac(0.2) + frac(0.5) + frac(0.0) + frac(0.2) +
         frac(0.5) + frac(0.3) + frac(0.5) + bytes([0x80]))
seeds["nozzle_drain.bin"] = create() + nozzle + drain + b"".join(step() for _ in range(12)) + \
    bytes([GET]) + W0 + bytes([2, 0x80, 0])

# 3. colliders: a kinematic sphere moved between steps, a static box, a plane.
sphere = bytes([NEW_COLLIDER]) + W0 + bytes([1, 4]) + u16(0) + frac(0.5) + frac(0.5) + frac(0.5) + \
    frac(0.5) + frac(0.5) + frac(0.5) + frac(0.5) + frac(0.5) + bytes([0x80])
box = bytes([NEW_COLLIDER]) + W0 + bytes([3, 0]) + u16(0) + frac(0.5) + frac(0.2) + frac(0.5) + \
    frac(0.5) + frac(0.5) + frac(0.5) + frac(0.5) + frac(0.5) + bytes([0x80])
pose = bytes([POSE]) + W0 + bytes([0]) + frac(0.6) + frac(0.6) + frac(0.5) + bytes([0])
seeds["colliders.bin"] = create() + emit() + sphere + box + pose + step() + pose + step() + \
    bytes([DEL_COLLIDER]) + W0 + bytes([0]) + step()

# 4. handles: stale and forged worlds after a destroy, and double destroy.
seeds["stale_handles.bin"] = create() + create() + bytes([DESTROY]) + W0 + step(world=STALE) + \
    step(world=FORGED) + bytes([DESTROY]) + STALE + emit() + step()

# 5. bad values: NaN dt, Inf gravity, NaN solver params, wrong struct sizes.
seeds["bad_values.bin"] = (create() + bytes([STEP]) + W0 + special(18) + bytes([GRAVITY]) + W0 + special(16) +
                           frac(0.5) + frac(0.5) + bytes([200]) + bytes([PARAMS]) + W0 + u16(0x0004) + special(18) +
                           bytes([0x80]) + bytes([GET]) + W0 + bytes([1, 0x80, 230, 2]) +
                           create(0x0106, bytes([240]) + struct.pack("<I", 1 << 30) + raw_f(1e-30) + bytes([0])))

os.makedirs(OUT, exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)
    print(f"{name}: {len(data)} bytes")
