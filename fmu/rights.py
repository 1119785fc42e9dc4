"""Who made the FMU and on what terms: modelDescription.xml's ``version``,
``author``, ``license`` and ``copyright`` (FMI 2.0 and 3.0 alike), and the
licence texts under ``documentation/licenses/`` (the FMI standard's place:
``license.txt`` the entry point, then each licence's text).

pdbfs is released under the BSD-3-Clause licence, and so, unless its user
states other terms, is the FMU: the model code pdbfs generated from the rig
and pdbfs's C wrapper around it (``pdbfs-LICENSE.txt``). ``author`` is left
out unless given. A licence or copyright given is the user's statement about
the model; the terms and holders of the code in the FMU that is not theirs
are kept after it: pdbfs's C wrapper, and SUNDIALS' CVODES compiled into
every binary (BSD-3-Clause too, its holders read from the licence shipped
with it).
"""
from __future__ import annotations

import re
from importlib import metadata
from pathlib import Path
from xml.sax.saxutils import quoteattr

from pdbfs.errors import ExportError

#: characters XML 1.0 cannot hold at all, even escaped
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")
#: the FMU's licence folder and its entry point (FMI 3.0, 2.5.1.1)
LICENSES_DIR = "documentation/licenses"
LICENSE_ENTRY = f"{LICENSES_DIR}/license.txt"
#: where the FMU keeps pdbfs's licence and SUNDIALS' (written with the documentation)
PDBFS_LICENSE_IN_FMU = f"{LICENSES_DIR}/pdbfs-LICENSE.txt"
LICENSE_IN_FMU = f"{LICENSES_DIR}/SUNDIALS-LICENSE"
#: pdbfs's licence (SPDX) and copyright holders
PDBFS_LICENSE = "BSD-3-Clause"
PDBFS_COPYRIGHT = "Copyright (c) 2026, The pdbfs developers"

_BSD3 = """\
BSD 3-Clause License

{copyright}
All rights reserved.

Redistribution and use in source and binary forms, with or without
modification, are permitted provided that the following conditions are met:

1. Redistributions of source code must retain the above copyright notice, this
   list of conditions and the following disclaimer.

2. Redistributions in binary form must reproduce the above copyright notice,
   this list of conditions and the following disclaimer in the documentation
   and/or other materials provided with the distribution.

3. Neither the name of the copyright holder nor the names of its
   contributors may be used to endorse or promote products derived from
   this software without specific prior written permission.

THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS"
AND ANY EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE
IMPLIED WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDER OR CONTRIBUTORS BE LIABLE
FOR ANY DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL
DAMAGES (INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR
SERVICES; LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER
CAUSED AND ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY,
OR TORT (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE
OF THIS SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE.
"""


def pdbfs_license_text() -> str:
    """pdbfs's licence: the BSD-3-Clause text with pdbfs's copyright line."""
    return _BSD3.format(copyright=PDBFS_COPYRIGHT)


def check_rights(**values: str | None) -> dict:
    """Check the rights an FMU is to carry, before any work.

    Parameters
    ----------
    **values : str or None
        ``author``, ``license``, ``copyright`` as given (None: the default).

    Returns
    -------
    dict
        The values, unchanged.

    Raises
    ------
    pdbfs.ExportError
        Naming the one that is not a string or cannot be written in XML.
    """
    for name, v in values.items():
        if v is None:
            continue
        if not isinstance(v, str):
            raise ExportError(f"{name} must be a string, not {type(v).__name__}")
        bad = _NOT_XML.search(v)
        if bad:
            raise ExportError(f"{name}: character {bad.group()!r} at position {bad.start()} cannot be "
                              "written in XML")
    return values


def _pdbfs_version() -> str | None:
    try:
        return metadata.version("pdbfs")
    except metadata.PackageNotFoundError:
        return None


def holders(license_file: Path | None) -> str | None:
    """The copyright line of a licence file ('Copyright (c) 2002-2024, ...'), if it has one."""
    try:
        text = license_file.read_text() if license_file else ""
    except OSError:
        return None
    line = next((ln.strip() for ln in text.splitlines() if ln.strip().lower().startswith("copyright")), None)
    return line.rstrip(".") if line else None


def _pdbfs() -> str:
    version = _pdbfs_version()
    return f"pdbfs {version}" if version else "pdbfs"


def rights_attrs(sundials: str, license_file: Path | None, shipped: bool, author: str | None = None,
                 license: str | None = None, copyright: str | None = None) -> list[str]:
    """The attribute lines of modelDescription.xml: ``sundials`` is the
    embedded SUNDIALS' version, ``license_file`` its licence, ``shipped``
    whether the FMU carries that file (at LICENSE_IN_FMU). Without a
    ``license`` the FMU is BSD-3-Clause as pdbfs; without a ``license`` or
    ``copyright`` its copyright is pdbfs's."""
    check_rights(author=author, license=license, copyright=copyright)
    cvode = f"SUNDIALS {sundials} CVODES, embedded"
    terms = f"{cvode}: BSD-3-Clause" + (f" ({LICENSE_IN_FMU})" if shipped else "")
    owner = holders(license_file)
    if license is None:       # the whole FMU is pdbfs's output: pdbfs's terms
        license = f"{PDBFS_LICENSE} (model code generated by {_pdbfs()}, and pdbfs's C wrapper: {PDBFS_LICENSE_IN_FMU})"
        copyright = copyright or PDBFS_COPYRIGHT
    else:                     # the user's terms for the model; the wrapper stays pdbfs's
        license += f"; {_pdbfs()}'s C wrapper: {PDBFS_LICENSE} ({PDBFS_LICENSE_IN_FMU})"
    if copyright != PDBFS_COPYRIGHT:
        copyright = "; ".join(p for p in (copyright, f"pdbfs's C wrapper: {PDBFS_COPYRIGHT}") if p)
    attrs = [("version", _pdbfs_version()), ("author", author or None),
             ("license", f"{license}; {terms}"),
             ("copyright", "; ".join(p for p in (copyright, f"{cvode}: {owner}" if owner else "") if p))]
    return [f"  {k}={quoteattr(v)}" for k, v in attrs if v]   # quoteattr escapes <&"' and line breaks


def license_txt(ident: str, rig: str, fmi_version: int, sundials: str, license_file: Path | None,
                shipped: bool, license: str | None = None, copyright: str | None = None) -> str:
    """documentation/licenses/license.txt: what in the FMU is under which
    licence, and whose copyright it is, naming the files of the licences'
    texts beside it."""
    owner = holders(license_file) or "see the SUNDIALS licence"
    if license is None:
        model = [f"  Licence:   {PDBFS_LICENSE}, as pdbfs below (pdbfs-LICENSE.txt)",
                 f"  Copyright: {copyright or PDBFS_COPYRIGHT}"]
    else:
        model = [f"  Licence:   {license}", f"  Copyright: {copyright or 'not stated'}"]
    headers = f"fmi{fmi_version}*.h"
    lines = [f"Licences of the FMU {ident} (the rig {rig}), exported by {_pdbfs()}", "",
             "The model (as modelDescription.xml states in license and copyright)", *model, "",
             "pdbfs: its C wrapper and the model code it generated from the rig (sources/*.c and",
             "sources/*.h but the FMI headers), compiled into every binary",
             f"  Licence:   {PDBFS_LICENSE}, pdbfs-LICENSE.txt", f"  Copyright: {PDBFS_COPYRIGHT}", "",
             f"SUNDIALS {sundials} CVODES: compiled into every binary"
             + (" (its sources in sources/sundials_src/ and sources/cvode/, sundials/, ...)" if shipped else ""),
             "  Licence:   BSD-3-Clause" + (", SUNDIALS-LICENSE" if shipped else ""), f"  Copyright: {owner}", "",
             f"The FMI {fmi_version}.0 standard headers (sources/{headers}): BSD-2-Clause, their terms and",
             "holders stated in each file", ""]
    return "\n".join(lines)
