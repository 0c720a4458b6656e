"""pytest fixtures for a virtual EtherCAT network (docs/control.md "Python").

Load it with ``pytest_plugins = ["ecatslave.pytest_plugin"]`` in a
conftest.py (or ``pytest -p ecatslave.pytest_plugin``). Then:

    def test_drive_reports_position(ecat_network, ecat_client):
        ecat_client.write(0, 0x6064, 0, 4096)
        ...  # run a master against ecat_network.master_udp

    @pytest.mark.ecat_network(count=3)          # three generic servos
    @pytest.mark.ecat_network(devices=["my.xml"], veth=True)  # root: a veth pair in a netns

Each test gets a network of its own, torn down afterwards even when the test
fails.
"""

import pytest

from ecatslave.network import VirtualNetwork


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "ecat_network(devices=(), count=1, veth=False, args=()): the virtual network the "
        "ecat_network fixture starts")


@pytest.fixture
def ecat_network(request):
    """A running ecat-slave with its control interface (VirtualNetwork)."""
    marker = request.node.get_closest_marker("ecat_network")
    options = dict(marker.kwargs) if marker else {}
    if options.get("veth"):
        import os
        if os.geteuid() != 0:
            pytest.skip("a veth network needs root")
    network = VirtualNetwork(**options)
    network.start()
    try:
        yield network
    finally:
        network.stop()


@pytest.fixture
def ecat_client(ecat_network):
    """A Client connected to ecat_network's control interface."""
    client = ecat_network.client()
    try:
        yield client
    finally:
        client.close()
