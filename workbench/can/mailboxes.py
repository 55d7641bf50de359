"""Mailbox assignment: the thesis's ``canMap`` (chapter 6.3.2).

There is one map per network and role (CAN2 RX, CAN2 TX, ...). The messages of a DBC take
the next free mailboxes of their map in the chosen order, so a second DBC on the same
network continues after the first: ``CAN2_MSG_TX_000``, ``CAN2_MSG_TX_001``, ...

The default order is the DBC file order (the first TX message of the file is
``CAN2_MSG_TX_000``). The thesis's own figures come from the reverse file order
(FLCU_TO_PCM_003 = CAN2_MSG_TX_000, C3RXAAA = CAN3_MSG_RX_031); ``id`` and ``name``
sort by frame id (standard before extended at equal ids) or by message name.
"""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Iterable

from workbench.can.model import Message, Role
from workbench.can.naming import mailbox_name

__all__ = ["CanMap", "MailboxOrder", "Mailboxes"]


class MailboxOrder(str, enum.Enum):
    """In which order a DBC's messages take their mailboxes."""

    FILE = "file"
    REVERSE = "reverse"
    ID = "id"
    NAME = "name"

    def arrange(self, messages: Iterable[Message]) -> list[Message]:
        """``messages`` (given in DBC file order) in this order."""
        messages = list(messages)
        if self is MailboxOrder.REVERSE:
            return messages[::-1]
        if self is MailboxOrder.ID:
            return sorted(messages, key=lambda m: (m.frame_id, m.extended))
        if self is MailboxOrder.NAME:
            return sorted(messages, key=lambda m: m.name)
        return messages


class CanMap:
    """The mailboxes of one network and role, and the message that holds each."""

    def __init__(self, network: str, role: Role):
        self.network = network
        self.role = role
        self.holders: list[str] = []
        """Message name per mailbox index."""

    def assign(self, message: Message) -> Message:
        """``message`` with the next free mailbox of this map."""
        mailbox = mailbox_name(self.network, self.role.value, len(self.holders))
        self.holders.append(message.name)
        return dataclasses.replace(message, mailbox=mailbox)


class Mailboxes:
    """All ``CanMap`` s of one import: a DBC after another takes the next free mailboxes."""

    def __init__(self, order: MailboxOrder = MailboxOrder.FILE):
        self.order = order
        self.maps: dict[tuple[str, Role], CanMap] = {}

    def assign(self, messages: Iterable[Message]) -> list[Message]:
        """Mailboxes for one DBC's messages (in file order); messages without a role get none.

        Returns the messages with a role, in mailbox order per network and role.
        """
        assigned = []
        for message in self.order.arrange(m for m in messages if m.role is not None):
            key = (message.network, message.role)
            can_map = self.maps.setdefault(key, CanMap(*key))
            assigned.append(can_map.assign(message))
        return assigned
