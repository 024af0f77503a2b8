#!/usr/bin/env python3
"""The soak run (issue 26): a simulated station used the way a lab uses it all day, with the
worst of what happens to one.

Leaves are captured back to back through `leafdig capture --simulate` (the simulated FASTRAK and
caliper on pseudo-terminals, the virtual technician): sample leaves and synthetic ones of every
serration, with random device faults and unplugged cables, the capture process killed with
SIGKILL at random instants and resumed (`sessions resume`), and now and then the disk filled to
the last byte under it (a tmpfs, when run as root) and freed again. Every so many leaves the
station pushes to a throw-away lab server (a PostgreSQL cluster of its own), and some pushes are
killed too. At the end:

  - every event the capture acknowledged (a JSON line with its seq) is in the station's file;
  - every item is stored once (one marker per row and point, one reading per kind and row);
  - `leafdig sessions verify --all` passes (chains, projections, pages);
  - the server holds exactly the station's events, session by session.

Usage: scripts/soak.py [--leaves N] [--minutes M] [--seed S] [--leafdig PATH]
       (defaults: 1000 leaves or 60 minutes, whichever comes first; build/ci's leafdig)
Plants join the soak once the plant protocol lands (docs/roadmap.md).
"""
import argparse
import json
import os
import pwd
import random
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SAMPLES = [os.path.join(ROOT, "data", "samples", f) for f in
           ("lower-leaf-n10.markers.json", "upper-curved-leaf-n14.markers.json", "upper-small-leaf-n17.markers.json")]
# Mostly small synthetic leaves of every shape and serration (a station's day is many leaves;
# 1 000 in an hour needs a few seconds each), now and then a whole sample leaf.
SYNTH = ["shape=ovate,serration=round,teeth=14,rows=3,length=150", "shape=obovate,rows=3,length=120",
         "shape=elliptic,serration=sharp,teeth=18,rows=4,length=160", "shape=oblong,serration=straight,rows=3,length=180",
         "shape=tobacco,serration=acuminate,rows=4,length=200", "shape=tobacco,rows=5,length=260"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    """A throw-away PostgreSQL cluster (initdb + pg_ctl in a temporary directory)."""

    def __init__(self, base):
        self.dir = os.path.join(base, "pg")
        os.makedirs(self.dir)
        bindir = subprocess.run(["pg_config", "--bindir"], capture_output=True, text=True).stdout.strip()
        if not os.path.exists(os.path.join(bindir, "initdb")):
            bindir = next(d for d in ("/usr/lib/postgresql/%s/bin" % v for v in ("17", "16", "15"))
                          if os.path.exists(d + "/initdb"))
        self.bin = bindir
        self.as_user = []
        if os.geteuid() == 0:
            pw = pwd.getpwnam("postgres")
            os.chown(self.dir, pw.pw_uid, pw.pw_gid)
            self.as_user = ["runuser", "-u", "postgres", "--"]
        self.log = os.path.join(self.dir, "log")
        self.run([self.bin + "/initdb", "-D", self.dir + "/data", "-U", "soak_admin", "--auth=trust", "-E", "UTF8",
                  "--locale=C", "--no-sync"])
        self.port = free_port()
        self.run([self.bin + "/pg_ctl", "-D", self.dir + "/data", "-w", "-t", "60", "-o",
                  "-p %d -k %s -c listen_addresses=127.0.0.1 -c fsync=off" % (self.port, self.dir), "start"])
        self.url = "postgresql://soak_admin@127.0.0.1:%d/postgres" % self.port

    def run(self, argv):
        with open(os.devnull, "w") as null:
            subprocess.run(self.as_user + argv, check=True, stdout=null, stderr=null, cwd="/")

    def psql(self, sql):
        out = subprocess.run(["psql", "-X", "-q", "-At", "-F", "\t", self.url, "-c", sql], check=True,
                             capture_output=True, text=True).stdout
        return [line.split("\t") for line in out.splitlines() if line]

    def stop(self):
        self.run([self.bin + "/pg_ctl", "-D", self.dir + "/data", "-m", "immediate", "-w", "stop"])


class SmallDisk:
    """The station's folder on a tmpfs (as root), so that 'disk full' is the kernel's ENOSPC."""

    def __init__(self, path, megabytes):
        self.path = path
        os.makedirs(path)
        self.mounted = os.geteuid() == 0 and subprocess.run(
            ["mount", "-t", "tmpfs", "-o", "size=%dm" % megabytes, "tmpfs", path]).returncode == 0
        self.filler = os.path.join(path, ".filler")

    def fill(self):
        """Writes a filler file until the file system refuses more (ENOSPC), unbuffered."""
        fd = os.open(self.filler, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
        try:
            for size in (1 << 20, 65536, 4096, 1):
                block = b"x" * size
                while True:
                    try:
                        os.write(fd, block)
                    except OSError:
                        break
        finally:
            os.close(fd)

    def free(self):
        if os.path.exists(self.filler):
            os.remove(self.filler)

    def release(self):
        if self.mounted:
            subprocess.run(["umount", "-l", self.path])


class Soak:
    def __init__(self, args):
        self.args = args
        self.rng = random.Random(args.seed)
        self.base = tempfile.mkdtemp(prefix="leafdig-soak-")
        os.chmod(self.base, 0o755)  # the cluster runs as the postgres user
        self.disk = SmallDisk(os.path.join(self.base, "station"), 768)
        self.db = os.path.join(self.disk.path, "station.sqlite")
        self.acks = {}  # session -> set of acknowledged seqs
        self.stats = {"leaves": 0, "captures": 0, "kills": 0, "disk_full": 0, "faulty": 0, "pushes": 0,
                      "pushes_killed": 0, "resumes": 0, "abandoned": 0}
        self.cluster = Cluster(self.base)
        self.leafdig([ "server", "init", "--url", self.cluster.url])
        pwfile = os.path.join(self.base, "tech.pw")
        with open(pwfile, "w") as f:
            f.write("soak-pw\n")
        self.leafdig(["server", "add-user", "--url", self.cluster.url, "--login", "soak_tech", "--role",
                      "technician", "--station", "soak-1", "--password-file", pwfile])
        self.tech = "postgresql://soak_tech:soak-pw@127.0.0.1:%d/postgres" % self.cluster.port

    def leafdig(self, argv, check=True):
        r = subprocess.run([self.args.leafdig] + argv, capture_output=True, text=True)
        if check and r.returncode != 0:
            raise SystemExit("soak: leafdig %s failed (%d): %s" % (" ".join(argv), r.returncode, r.stderr))
        return r

    # One run of capture (new or resumed), killed or starved of disk at random: returns the
    # session id and whether the leaf is complete.
    def capture_once(self, argv):
        p = subprocess.Popen([self.args.leafdig] + argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, text=True, bufsize=1)
        self.stats["captures"] += 1
        state = {"session": None, "complete": False}

        def read():
            for line in p.stdout:
                try:
                    j = json.loads(line)
                except ValueError:
                    continue
                if j.get("event") == "session":
                    state["session"] = j["session"]
                    self.acks.setdefault(j["session"], set())
                elif state["session"] is not None and j.get("event") not in ("prompt", "session", None):
                    # The event this line announces: an undo names its own in event_seq (its
                    # seq is the item's); seq 0 announces what was not recorded (disk full).
                    seq = j.get("event_seq", j.get("seq", 0))
                    if seq:
                        self.acks[state["session"]].add(seq)
                if j.get("event") == "complete":
                    state["complete"] = True

        reader = threading.Thread(target=read, daemon=True)
        reader.start()
        roll = self.rng.random()
        if roll < 0.3:
            time.sleep(self.rng.uniform(0.2, 3.0))
            if p.poll() is None:
                p.send_signal(signal.SIGKILL)
                self.stats["kills"] += 1
        elif roll < 0.4 and self.disk.mounted:
            time.sleep(self.rng.uniform(0.3, 2.0))
            if p.poll() is None:
                self.disk.fill()
                self.stats["disk_full"] += 1
                time.sleep(1.5)
                self.disk.free()
                try:
                    p.stdin.write("resume\n")
                    p.stdin.flush()
                except OSError:
                    pass
        # A virtual technician that gets lost (it happens after unplugs at speed 20: it keeps
        # pressing where the station already has a point) gives up as a person would: it
        # abandons the session, which then counts as done.
        try:
            p.wait(timeout=self.args.leaf_seconds)
        except subprocess.TimeoutExpired:
            self.stats["abandoned"] += 1
            try:
                p.stdin.write("abandon soak: the virtual technician got lost\n")
                p.stdin.flush()
            except OSError:
                pass
            try:
                p.wait(timeout=60)
            except subprocess.TimeoutExpired:
                p.kill()
                raise SystemExit("soak: a capture did not end within a minute of being abandoned: %s" % " ".join(argv))
        reader.join(timeout=10)
        if state["session"] is not None and not state["complete"]:
            con = sqlite3.connect("file:%s?mode=ro" % self.db, uri=True)
            row = con.execute("SELECT status FROM sessions WHERE id = ?", (state["session"],)).fetchone()
            con.close()
            if row and row[0] == "abandoned":
                state["complete"] = True
        return state["session"], state["complete"]

    def capture_leaf(self, n):
        leaf = self.rng.choice(SAMPLES) if self.rng.random() < 0.05 else self.rng.choice(SYNTH)
        what = ["--markers", leaf] if leaf.endswith(".json") else ["--synth", leaf]
        argv = ["capture", "--simulate", "--json", "--speed", "50", "--station", "soak-1", "--db", self.db,
                "--project", "soak", "--plant", "P-%d" % (n // 10), "--leaf-position", str(n % 10 + 1),
                "--seed", str(self.rng.randrange(1 << 30))] + what
        if self.rng.random() < 0.3:
            argv += ["--faults", "garbage=0.002,unplug=0.0008:0.3,seed=%d" % self.rng.randrange(1000)]
            self.stats["faulty"] += 1
        session, complete = self.capture_once(argv)
        tries = 0
        while not complete:
            if session is None:
                # Killed before the session was made: nothing acknowledged, start again.
                session, complete = self.capture_once(argv)
                continue
            tries += 1
            if tries > 40:
                raise SystemExit("soak: session %s never completed" % session)
            self.stats["resumes"] += 1
            _, complete = self.capture_once(["sessions", "resume", str(session), "--simulate", "--json", "--speed", "50",
                                             "--db", self.db])
        self.stats["leaves"] += 1

    def push(self, may_kill):
        self.stats["pushes"] += 1
        p = subprocess.Popen([self.args.leafdig, "sync", "push", "--db", self.db, "--to", self.tech, "--batch", "50"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if may_kill and self.rng.random() < 0.3:
            time.sleep(self.rng.uniform(0.05, 1.0))
            if p.poll() is None:
                p.send_signal(signal.SIGKILL)
                self.stats["pushes_killed"] += 1
        p.wait()

    def check(self):
        problems = []
        con = sqlite3.connect("file:%s?mode=ro" % self.db, uri=True)
        for session, seqs in self.acks.items():
            stored = {r[0] for r in con.execute("SELECT seq FROM events WHERE session_id = ?", (session,))}
            lost = seqs - stored
            if lost:
                problems.append("session %d: acknowledged events %s are not stored" % (session, sorted(lost)[:10]))
        for table, key in (("markers", "what, row, col"), ("thickness_readings", "what, row, col")):
            for row in con.execute("SELECT session_id, %s, count(*) FROM %s GROUP BY session_id, %s HAVING count(*) > 1"
                                   % (key, table, key)):
                problems.append("%s stored twice: %s" % (table, row))
        station = {}
        for sid, station_id, seq, h in con.execute(
                "SELECT e.session_id, s.station, e.seq, e.hash FROM events e JOIN sessions s ON s.id = e.session_id"):
            station.setdefault(sid, []).append((seq, h))
        con.close()
        verify = self.leafdig(["sessions", "verify", "--all", "--db", self.db], check=False)
        if verify.returncode != 0:
            problems.append("sessions verify --all failed: %s" % (verify.stdout + verify.stderr)[-2000:])
        server = {}
        for sid, seq, h in self.cluster.psql(
                "SELECT s.station_session_id, e.seq, e.hash FROM leafdig.events e JOIN leafdig.sessions s "
                "ON s.id = e.session_id ORDER BY 1, 2"):
            server.setdefault(int(sid), []).append((int(seq), h))
        for sid in station:
            if sorted(station[sid]) != server.get(sid, []):
                problems.append("session %d: the server's events differ from the station's" % sid)
        if set(server) - set(station):
            problems.append("the server holds sessions the station does not: %s" % sorted(set(server) - set(station)))
        return problems, sum(len(v) for v in station.values())

    def run(self):
        start = time.time()
        deadline = start + 60 * self.args.minutes
        n = 0
        try:
            while n < self.args.leaves and time.time() < deadline:
                self.capture_leaf(n)
                n += 1
                if n % self.args.push_every == 0:
                    self.push(may_kill=True)
                if n % 50 == 0:
                    print("soak: %d leaves in %.0f s %s" % (n, time.time() - start, self.stats), flush=True)
            self.push(may_kill=False)
            problems, events = self.check()
        finally:
            self.cluster.stop()
            self.disk.release()
            shutil.rmtree(self.base, ignore_errors=True)
        elapsed = time.time() - start
        print("soak: %d leaves, %d events in %.0f s (%.1f leaves a minute); %s; disk %s" % (
            self.stats["leaves"], events, elapsed, 60 * self.stats["leaves"] / elapsed, self.stats,
            "a 768 MB tmpfs filled to ENOSPC" if self.disk.mounted else "not filled (not root)"))
        for p in problems:
            print("soak: PROBLEM: " + p, file=sys.stderr)
        if problems:
            return 1
        print("soak: every acknowledged event stored once, every chain verifies, station and server agree")
        return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--leaves", type=int, default=1000)
    parser.add_argument("--minutes", type=float, default=60)
    parser.add_argument("--seed", type=int, default=20261125)
    parser.add_argument("--push-every", type=int, default=20)
    parser.add_argument("--leaf-seconds", type=float, default=120,
                        help="a capture run longer than this is abandoned (the virtual technician got lost)")
    parser.add_argument("--leafdig", default=os.path.join(ROOT, "build", "ci", "ui", "cli", "leafdig"))
    args = parser.parse_args()
    return Soak(args).run()


if __name__ == "__main__":
    sys.exit(main())
