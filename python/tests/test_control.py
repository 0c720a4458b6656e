"""The ecatslave package against a real ecat-slave over UDP on loopback
(no root): the network view, objects and process data read and written
directly, events streamed while ecat-master brings the slaves to Op, faults,
and bad input answered with an error while the slaves keep running."""

import json
import os
import shutil
import socket
import subprocess
import time

import pytest

from ecatslave import Client, ControlError


def master_program():
    return os.environ.get("ECAT_MASTER") or shutil.which("ecat-master")


def steady_network(client, timeout=3.0):
    """The network view once two reads 150 ms apart agree: without a master
    the ESC's PDI watchdog expires once, 100 ms after start (0x0443, DL
    status bit 1), which is not what a test of bad input compares."""
    deadline = time.monotonic() + timeout
    last = client.network()["slaves"]
    while time.monotonic() < deadline:
        time.sleep(0.15)
        now = client.network()["slaves"]
        if now == last:
            return now
        last = now
    raise AssertionError("the network did not settle")


@pytest.mark.ecat_network(count=2)
def test_network_shows_both_slaves_in_order(ecat_client):
    hello = ecat_client.hello()
    assert hello["protocol"] == 1
    assert hello["slaves"] == 2
    assert hello["faults"] is True
    assert hello["simulated"] is False
    slaves = ecat_client.network()["slaves"]
    assert [s["position"] for s in slaves] == [0, 1]
    assert [s["name"] for s in slaves] == ["slave-1", "slave-2"]
    for s in slaves:
        assert s["device"] == "Generic servo"
        assert s["identity"] == {"vendor_id": 0, "product_code": 0x402, "revision": 0x10000, "serial": 0}
        assert s["al_state"] == "INIT"
        assert s["al_status"] == 0x0001
        assert s["al_status_code"] == 0
        assert len(s["ports"]) == 4
    # The first slave's port 1 is cabled to the second; the last one's is open.
    assert slaves[0]["ports"][1]["link"] is True
    assert slaves[1]["ports"][1]["link"] is False


def test_objects_read_and_written_directly(ecat_client):
    assert ecat_client.read(0, "0x1008") == "Generic servo"
    assert ecat_client.read(0, 0x1018, 2) == 0x402
    assert ecat_client.write(0, 0x6064, 0, -12345) == -12345
    entry = ecat_client.entry(0, 0x6064)
    assert entry == {"index": 0x6064, "subindex": 0, "name": "Position actual value", "type": "INTEGER32",
                     "value": -12345, "hex": "c7cfffff"}
    assert ecat_client.write(0, 0x6041, 0, {"hex": "3712"}) == 0x1237


def test_process_data_by_name(ecat_client):
    names = [e["name"] for e in ecat_client.pdo(0)]
    assert "Statusword" in names and "Controlword" in names
    assert ecat_client.pdo(0, "Position actual value", 777) == 777
    assert ecat_client.read(0, 0x6064) == 777
    assert ecat_client.pdo(0, "Position actual value") == 777


def test_bad_input_gets_an_error_and_changes_nothing(ecat_network, ecat_client):
    ecat_client.write(0, 0x6064, 0, 42)
    before = steady_network(ecat_client)
    cases = [
        (lambda: ecat_client.read(5, 0x6064), "unknown_slave"),
        (lambda: ecat_client.read(0, 0x5555), "unknown_object"),
        (lambda: ecat_client.read(0, 0x1018, 9), "unknown_subindex"),
        (lambda: ecat_client.write(0, 0x1008, 0, "x"), "read_only"),
        (lambda: ecat_client.write(0, 0x6064, 0, "12"), "bad_value"),
        (lambda: ecat_client.write(0, 0x6040, 0, 65536), "out_of_range"),
        (lambda: ecat_client.pdo(0, "Temperature"), "unknown_pdo_entry"),
        (lambda: ecat_client.engage_fault("meteor"), "unknown_fault"),
        (lambda: ecat_client.clear_fault(99), "unknown_fault"),
        (lambda: ecat_client.step(1), "not_simulated"),
        (lambda: ecat_client.request("explode"), "unknown_command"),
    ]
    for call, code in cases:
        with pytest.raises(ControlError) as err:
            call()
        assert err.value.code == code, err.value
    # Malformed lines on a raw connection, then a good one on the same connection.
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as raw:
        raw.settimeout(5)
        raw.connect(ecat_network.control)
        raw.sendall(b"{not json\n[1]\n{\"id\":3,\"cmd\":\"hello\"}\n")
        data = b""
        while data.count(b"\n") < 3:
            data += raw.recv(65536)
        replies = [json.loads(line) for line in data.splitlines()]
        assert replies[0] == {"id": None, "error": {"code": "bad_json", "message": "the line is not one JSON value"}}
        assert replies[1]["error"]["code"] == "bad_request"
        assert replies[2]["id"] == 3 and replies[2]["result"]["protocol"] == 1
    assert ecat_client.read(0, 0x6064) == 42
    assert ecat_client.network()["slaves"] == before
    assert ecat_network.process.poll() is None


def test_a_client_that_leaves_mid_stream_changes_nothing(ecat_network, ecat_client):
    stream = ecat_client.subscribe()
    fault = ecat_client.engage_fault("link_cut", slave=0, port=0)
    stream.sock.close()  # gone with events pending
    ecat_client.clear_fault(fault)
    assert ecat_client.faults() == []
    assert ecat_client.hello()["slaves"] == 1
    with ecat_network.client() as again:
        assert again.network()["slaves"][0]["ports"][0]["link"] is True


@pytest.mark.ecat_network(count=2)
def test_faults_engaged_and_cleared_with_events(ecat_client):
    kinds = {k["name"] for k in ecat_client.fault_kinds()}
    assert {"link_cut", "drop_frames", "al_error"} <= kinds
    with ecat_client.subscribe() as stream:
        fault = ecat_client.engage_fault("link_cut", slave=0, port=1)
        engaged = stream.wait_for(type="fault_engaged")
        assert engaged["fault"] == fault and engaged["kind"] == "link_cut"
        assert engaged["slave"] == 0 and engaged["port"] == 1
        link = stream.wait_for(type="link", slave=0, port=1)
        assert link["up"] is False
        assert ecat_client.faults() == [{"fault": fault, "kind": "link_cut", "slave": 0, "port": 1, "params": {}}]
        assert ecat_client.network()["slaves"][0]["ports"][1]["link"] is False
        ecat_client.clear_fault(fault)
        assert stream.wait_for(type="fault_cleared")["fault"] == fault
        assert stream.wait_for(type="link", slave=0, port=1)["up"] is True
    assert ecat_client.faults() == []


def test_master_bringing_the_slave_to_op_is_seen_as_events(ecat_network, ecat_client):
    master = master_program()
    if not master:
        pytest.skip("ecat-master not found (set ECAT_MASTER)")
    with ecat_client.subscribe() as stream:
        run = subprocess.run([master, "--udp", ecat_network.master_udp, "--cycles", "300", "-q"],
                             capture_output=True, text=True, timeout=60)
        assert run.returncode == 0, run.stderr + run.stdout
        requested = stream.wait_for(type="al_control", slave=0, requested="OP")
        assert requested["error_ack"] is False
        op = stream.wait_for(type="al_state", slave=0, to="OP")
        assert op["error"] is False and op["al_status_code"] == 0
    # Events stay in the queue for a client that polls.
    types = {e["type"] for e in ecat_client.events(since=0)["events"]}
    assert {"al_control", "al_state"} <= types


@pytest.mark.ecat_network(veth=True)
def test_veth_network_in_its_own_namespace(ecat_network, ecat_client):
    """Root only (the fixture skips otherwise): the slave end of the veth pair
    lives in a network namespace; the master runs on the other end."""
    master = master_program()
    if not master or not shutil.which("ip"):
        pytest.skip("needs ecat-master and iproute2")
    links = subprocess.run(["ip", "-n", ecat_network.netns, "-o", "link", "show"], capture_output=True, text=True)
    assert ecat_network.slave_iface in links.stdout
    with ecat_client.subscribe() as stream:
        run = subprocess.run([master, "--iface", ecat_network.master_iface, "--cycles", "200", "-q"],
                             capture_output=True, text=True, timeout=60)
        assert run.returncode == 0, run.stderr + run.stdout
        stream.wait_for(type="al_state", slave=0, to="OP")
