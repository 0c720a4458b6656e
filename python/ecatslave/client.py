"""Client of the ecat-slave control interface: JSON lines over a Unix socket
or TCP (docs/control.md). Every method sends one request and returns the
reply's "result"; an error reply raises ControlError with its code."""

import itertools
import json
import socket
import time


class ControlError(Exception):
    """An error reply: .code is the protocol's code ("unknown_slave", ...)."""

    def __init__(self, code, message, reply=None):
        super().__init__(f"{code}: {message}")
        self.code = code
        self.message = message
        self.reply = reply


def _connect(address, timeout):
    """address: a Unix socket path, (host, port), or "host:port"."""
    if isinstance(address, tuple):
        host, port = address
        return socket.create_connection((host, int(port)), timeout=timeout)
    if isinstance(address, str) and "/" not in address and ":" in address:
        host, _, port = address.rpartition(":")
        return socket.create_connection((host.strip("[]"), int(port)), timeout=timeout)
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    sock.settimeout(timeout)
    sock.connect(str(address))
    return sock


class _Lines:
    """Reads newline-terminated JSON values from a socket."""

    def __init__(self, sock):
        self.sock = sock
        self.buffer = b""

    def read(self, timeout):
        deadline = time.monotonic() + timeout
        while b"\n" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no reply from the control interface")
            self.sock.settimeout(left)
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("the control interface closed the connection")
            self.buffer += chunk
        line, _, self.buffer = self.buffer.partition(b"\n")
        return json.loads(line)


class _Connection:
    """A socket to the control interface, closed on leaving a with block."""

    def close(self):
        self.sock.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Client(_Connection):
    """One connection to the control interface.

    >>> with Client("/tmp/ecat.sock") as c:
    ...     c.network()["slaves"][0]["al_state"]
    'INIT'
    """

    def __init__(self, address, timeout=5.0):
        self.address = address
        self.timeout = timeout
        self.sock = _connect(address, timeout)
        self._lines = _Lines(self.sock)
        self._ids = itertools.count(1)


    # --- the protocol ---
    def request(self, cmd, **fields):
        """Sends {"cmd": cmd, **fields}; returns "result" or raises ControlError."""
        rid = next(self._ids)
        message = dict(fields, cmd=cmd, id=rid)
        self.sock.sendall(json.dumps(message).encode() + b"\n")
        while True:
            reply = self._lines.read(self.timeout)
            if reply.get("id") == rid or (reply.get("id") is None and "error" in reply):
                break
        if "error" in reply:
            err = reply["error"]
            raise ControlError(err.get("code"), err.get("message"), reply)
        return reply["result"]

    def hello(self):
        return self.request("hello")

    def network(self):
        """The slaves in topology order with registers and counters."""
        return self.request("network")

    def slave(self, slave):
        return self.request("slave", slave=slave)

    def entry(self, slave, index, subindex=0):
        """The whole entry: index, subindex, name, type, value, hex."""
        return self.request("read", slave=slave, index=index, subindex=subindex)

    def read(self, slave, index, subindex=0):
        """The value of an object entry, read in the object store directly."""
        return self.entry(slave, index, subindex)["value"]

    def write(self, slave, index, subindex, value):
        """Sets an entry as the device itself would (not through the mailbox);
        returns the value read back. value: a number, bool, string, or
        {"hex": "..."} for raw little-endian bytes."""
        return self.request("write", slave=slave, index=index, subindex=subindex, value=value)["value"]

    def pdo(self, slave, name=None, value=None):
        """Without name: every process-data entry of the slave. With name:
        that entry's value, or writes it when value is given."""
        if name is None:
            return self.request("pdo", slave=slave)["entries"]
        if value is None:
            return self.request("pdo", slave=slave, name=name)["value"]
        return self.request("pdo", slave=slave, name=name, value=value)["value"]

    def events(self, since=0, max=1000):  # noqa: A002 - the protocol's field name
        """{"events": [...], "next": N, "lost": M}: events with seq >= since."""
        return self.request("events", since=since, max=max)

    def subscribe(self, since=None):
        """A new connection that streams events (see EventStream)."""
        return EventStream(self.address, since=since, timeout=self.timeout)

    # --- faults (docs/faults.md) ---
    def fault_kinds(self):
        return self.request("fault_kinds")["kinds"]

    def engage_fault(self, kind, slave=None, port=None, **params):
        fields = {"kind": kind, "params": params}
        if slave is not None:
            fields["slave"] = slave
        if port is not None:
            fields["port"] = port
        return self.request("fault_engage", **fields)["fault"]

    def clear_fault(self, fault):
        return self.request("fault_clear", fault=fault)

    def clear_all_faults(self):
        return self.request("fault_clear", all=True)

    def faults(self):
        return self.request("faults")["faults"]

    # --- simulated time (in-process networks) ---
    def pause(self):
        return self.request("pause")

    def run(self):
        return self.request("run")

    def step(self, cycles=1):
        return self.request("step", cycles=cycles)

    def time(self):
        return self.request("time")


class EventStream(_Connection):
    """Events pushed by the control interface as they happen (sampled every
    10 ms), on a connection of their own."""

    def __init__(self, address, since=None, timeout=5.0):
        self.sock = _connect(address, timeout)
        self._lines = _Lines(self.sock)
        message = {"cmd": "subscribe", "id": 1}
        if since is not None:
            message["since"] = since
        self.sock.sendall(json.dumps(message).encode() + b"\n")
        reply = self._lines.read(timeout)
        if "error" in reply:
            raise ControlError(reply["error"]["code"], reply["error"]["message"], reply)
        self.next = reply["result"]["next"]

    def get(self, timeout=5.0):
        """The next event (a dict); TimeoutError when none comes in time."""
        while True:
            line = self._lines.read(timeout)
            if "event" in line:
                return line["event"]

    def wait_for(self, timeout=5.0, **match):
        """The first event whose fields equal every keyword given, e.g.
        wait_for(type="al_state", slave=0, to="OP"); earlier ones are skipped."""
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"no event matching {match}")
            event = self.get(left)
            if all(event.get(k) == v for k, v in match.items()):
                return event

