"""The message table of one node over one or more DBCs (what the thesis's Import DBC shows).

Each DBC belongs to a network (CAN1–CAN4): given explicitly, or read from the file name
(``FLCU_CAN2.dbc`` → CAN2); a table of a DBC whose name says none may assume one
(:data:`ASSUMED_NETWORK`, the vehicle bus of the thesis's layout). Messages the node
sends are TX, those it receives are RX; mailboxes follow :mod:`workbench.can.mailboxes`.
A message whose id and format appear twice on one network has ``unique_id`` False (the
thesis's UniqueID flag).
"""

from __future__ import annotations

import dataclasses
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from workbench.can.dbc_file import DbcFile, load_dbc
from workbench.can.mailboxes import Mailboxes, MailboxOrder
from workbench.can.model import Message, Role, messages_of
from workbench.can.naming import CAN_NETWORKS
from workbench.errors import InputError

__all__ = ["ASSUMED_NETWORK", "CanTable", "build_table", "guess_network", "load_networks", "network_of"]

ASSUMED_NETWORK = "CAN2"  # CAN2 is the vehicle bus in the thesis's layout: where a third-party DBC belongs
_NETWORK_IN_NAME = re.compile(r"(?<![A-Za-z0-9])(CAN[1-4])(?![0-9])", re.IGNORECASE)
_ROLE_ORDER = {Role.TX: 0, Role.RX: 1}


@dataclass(frozen=True)
class CanTable:
    """The messages of the chosen node (or of the whole DBCs when no node is chosen)."""

    node: str | None
    order: MailboxOrder
    messages: tuple[Message, ...]
    """With a node: its TX then RX messages per network, in mailbox order.
    Without a node: every message in file order, no roles and no mailboxes."""
    others: tuple[Message, ...] = ()
    """Messages the node neither sends nor receives (not in its table)."""

    def to_dict(self) -> dict:
        return {
            "node": self.node,
            "order": self.order.value,
            "messages": [message.to_dict() for message in self.messages],
            "not_in_table": [message.name for message in self.others],
        }


def guess_network(path: str | Path) -> str | None:
    """The one ``CAN1``–``CAN4`` in a DBC's file name (``FLCU_CAN2.dbc`` → CAN2), else ``None``."""
    found = {match.upper() for match in _NETWORK_IN_NAME.findall(Path(path).stem)}
    return found.pop() if len(found) == 1 else None


def network_of(path: str | Path, network: str | None = None, *, assume: str | None = None) -> str:
    """The network of a DBC: ``network`` when given, else :func:`guess_network`, else ``assume``.

    :raises InputError: ``network`` is not CAN1–CAN4, or the file name names none (or several)
        and nothing is assumed.
    """
    if network is not None:
        if network.upper() not in CAN_NETWORKS:
            raise InputError(f"unknown network {network!r} (expected one of {', '.join(CAN_NETWORKS)})")
        return network.upper()
    guessed = guess_network(path) or assume
    if guessed is None:
        raise InputError(f"{path}: cannot tell the network from the file name; give --network CAN1..CAN4")
    return guessed


def load_networks(paths: Sequence[str | Path], network: str | None = None, *,
                  assume: str | None = None) -> list[tuple[DbcFile, str]]:
    """Load each DBC with its network (see :func:`network_of`).

    :raises InputError: a file cannot be loaded or its network is unknown.
    """
    return [(load_dbc(path), network_of(path, network, assume=assume)) for path in paths]


def build_table(dbcs: Sequence[tuple[DbcFile, str]], node: str | None, order: MailboxOrder = MailboxOrder.FILE) -> CanTable:
    """The table of ``node`` over ``dbcs`` (DBC, network) pairs, mailboxes in ``order``.

    :raises InputError: ``node`` is not a node of one of the DBCs.
    """
    per_dbc = _mark_unique_ids([messages_of(dbc, network, node) for dbc, network in dbcs])
    everything = [message for messages in per_dbc for message in messages]
    if node is None:
        return CanTable(None, order, tuple(everything))
    mailboxes = Mailboxes(order)
    table = [message for messages in per_dbc for message in mailboxes.assign(messages)]
    networks = list(dict.fromkeys(network for _, network in dbcs))
    table.sort(key=lambda m: (networks.index(m.network), _ROLE_ORDER[m.role]))  # stable: mailbox order stays
    others = tuple(m for m in everything if m.role is None)
    return CanTable(node, order, tuple(table), others)


def _mark_unique_ids(per_dbc: list[list[Message]]) -> list[list[Message]]:
    def key(m: Message) -> tuple:
        return (m.network, m.frame_id, m.extended)

    counts = Counter(key(m) for messages in per_dbc for m in messages)
    return [[dataclasses.replace(m, unique_id=counts[key(m)] == 1) for m in messages] for messages in per_dbc]
