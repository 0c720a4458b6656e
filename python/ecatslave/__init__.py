"""ecatslave: drive a virtual EtherCAT network from a test.

A client of the control interface of ``ecat-slave --control`` (docs/control.md)
and a pytest plugin whose fixtures start a virtual network and tear it down.
Standard library only.
"""

from ecatslave.client import Client, ControlError, EventStream
from ecatslave.network import VirtualNetwork, NetworkError

__all__ = ["Client", "ControlError", "EventStream", "VirtualNetwork", "NetworkError"]
__version__ = "0.1.0"
