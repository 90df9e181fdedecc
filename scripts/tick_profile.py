# Run inside gdb by scripts/tick-profile.sh: connects to QEMU's gdb server, stops at the call of
# fw::Vehicle::tick numbered PA_TICK (from 0), single-steps it until it returns to its caller and
# writes the address of every instruction it executed, one per line, to PA_PCS (only when it
# stepped the whole tick).
import os

import gdb

tick = int(os.environ["PA_TICK"])
gdb.execute("set pagination off")
gdb.execute("set confirm off")
gdb.execute("target remote 127.0.0.1:" + os.environ["PA_PORT"])

entry = gdb.Breakpoint("fw::Vehicle::tick", internal=True)
entry.ignore_count = tick
gdb.execute("continue")
if entry.hit_count != tick + 1:
    raise gdb.GdbError("tick-profile: the image stopped before tick %d" % tick)
entry.delete()

# The tick ends where it returns to: the link register's address (Thumb bit cleared) with the
# stack no deeper than at the entry (a recursive call would pass the address deeper).
return_to = int(gdb.parse_and_eval("$lr")) & ~1
entry_sp = int(gdb.parse_and_eval("$sp"))
# A tick is a few thousand instructions; one that does not return within a hundred times its
# budget is reported, not stepped forever.
LIMIT = 150000
pcs = []
while True:
    pc = int(gdb.parse_and_eval("$pc"))
    if pc == return_to and int(gdb.parse_and_eval("$sp")) >= entry_sp:
        break
    if len(pcs) == LIMIT:
        raise gdb.GdbError("tick-profile: tick %d did not return within %d instructions" % (tick, LIMIT))
    pcs.append(pc)
    gdb.execute("stepi", to_string=True)
gdb.execute("kill")
# Written only once the whole tick is stepped: an absent file is a failure.
with open(os.environ["PA_PCS"], "w") as out:
    out.write("".join("%x\n" % pc for pc in pcs))
