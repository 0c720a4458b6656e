"""A virtual EtherCAT network in a child process: ecat-slave with its
control interface on a Unix socket, served over EtherCAT-in-UDP on loopback
(no root needed) or on a veth pair whose slave end lives in a network
namespace of its own (root). stop() tears everything down."""

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

from ecatslave.client import Client


class NetworkError(Exception):
    """The network could not be started (the message has ecat-slave's stderr)."""


def find_program(name, env_var):
    """$ENV_VAR if set, else the program on PATH."""
    path = os.environ.get(env_var) or shutil.which(name)
    if not path:
        raise NetworkError(f"{name} not found: set {env_var} or put it on PATH")
    return path


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _run(*args):
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


class VirtualNetwork:
    """ecat-slave with --control, started by start() and ended by stop().

    devices: device files in chain order (none: the built-in generic servo);
    count: number of slaves (copies of the last device); veth: serve a veth
    pair in a network namespace instead of UDP (needs root and iproute2);
    args: more ecat-slave options.

    Afterwards: .control (socket path), .udp_port and .master_udp
    ("127.0.0.1:PORT", for ecat-master --udp) or .master_iface (veth mode).
    """

    def __init__(self, devices=(), count=1, veth=False, args=(), program=None, start_timeout=10.0):
        self.devices = list(devices)
        self.count = count
        self.veth = veth
        self.args = list(args)
        self.program = program or find_program("ecat-slave", "ECAT_SLAVE")
        self.start_timeout = start_timeout
        self.process = None
        self.workdir = None
        self.control = None
        self.udp_port = None
        self.master_udp = None
        self.master_iface = None
        self.netns = None
        self._log = None

    def command(self):
        cmd = [self.program, "--control", self.control]
        for d in self.devices:
            cmd += ["--device", str(d)]
        if self.count != 1:
            cmd += ["--count", str(self.count)]
        if self.veth:
            # Root opens the raw socket; kept so that ecat-slave can still
            # create its control socket in the test's directory (it would
            # otherwise drop to SUDO_UID or nobody first).
            cmd += ["--iface", self.slave_iface, "--keep-privileges"]
        else:
            cmd += ["--udp", str(self.udp_port)]
        return cmd + self.args

    def _make_veth(self):
        if os.geteuid() != 0:
            raise NetworkError("a veth network needs root (use UDP instead)")
        tag = f"{os.getpid() % 100000}"
        self.netns = f"ecatslave-{tag}"
        self.master_iface = f"ecm{tag}"
        self.slave_iface = f"ecs{tag}"
        _run("ip", "netns", "add", self.netns)
        _run("ip", "link", "add", self.master_iface, "type", "veth", "peer", "name", self.slave_iface)
        _run("ip", "link", "set", self.slave_iface, "netns", self.netns)
        _run("ip", "link", "set", self.master_iface, "up")
        _run("ip", "netns", "exec", self.netns, "ip", "link", "set", self.slave_iface, "up")
        _run("ip", "netns", "exec", self.netns, "ip", "link", "set", "lo", "up")

    def start(self):
        self.workdir = tempfile.mkdtemp(prefix="ecatslave-")
        self.control = os.path.join(self.workdir, "control.sock")
        cmd = None
        try:
            if self.veth:
                self._make_veth()
                cmd = ["ip", "netns", "exec", self.netns] + self.command()
            else:
                self.udp_port = free_udp_port()
                self.master_udp = f"127.0.0.1:{self.udp_port}"
                cmd = self.command()
            self._log = open(os.path.join(self.workdir, "ecat-slave.log"), "w+b")
            self.process = subprocess.Popen(cmd, stdout=self._log, stderr=subprocess.STDOUT)
            self._wait_ready()
        except BaseException:
            self.stop()
            raise
        return self

    def _wait_ready(self):
        deadline = time.monotonic() + self.start_timeout
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise NetworkError(f"ecat-slave exited with {self.process.returncode}: {self.log()}")
            if os.path.exists(self.control):
                try:
                    with Client(self.control, timeout=1.0) as c:
                        c.hello()
                    return
                except OSError:
                    pass
            time.sleep(0.02)
        raise NetworkError(f"ecat-slave's control socket did not answer in {self.start_timeout} s: {self.log()}")

    def log(self):
        """What ecat-slave printed so far."""
        if not self._log:
            return ""
        self._log.flush()
        with open(self._log.name, "rb") as f:
            return f.read().decode(errors="replace")

    def client(self, timeout=5.0):
        return Client(self.control, timeout=timeout)

    def stop(self):
        """Ends ecat-slave (SIGTERM, then SIGKILL) and removes what start() made."""
        if self.process and self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self.netns:
            subprocess.run(["ip", "netns", "del", self.netns], stderr=subprocess.DEVNULL, check=False)
            # The master end goes with its peer; delete it in case the peer never moved.
            subprocess.run(["ip", "link", "del", self.master_iface], stderr=subprocess.DEVNULL, check=False)
            self.netns = None
        if self._log:
            self._log.close()
        if self.workdir:
            shutil.rmtree(self.workdir, ignore_errors=True)
            self.workdir = None

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
