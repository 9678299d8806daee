"""The OSP model descriptions `fmu-pack pack` writes validate against the official OSP-IS 1.0
schema: `OspModelDescription-1.0.0.xsd` of open-simulation-platform's osp-validator, kept in
tests/data/osp (its README names the source and the licences), for the default FMU (the
semicircle) and a ship FMU (rigid DOFs and an elastic mode). The copy inside the archive is
the same file.
"""
import re
import subprocess
import zipfile

import pytest
import xmlschema

from conftest import ROOT

SCHEMA = ROOT / "tests" / "data" / "osp" / "OspModelDescription-1.0.0.xsd"
ARCHIVE_DIR = "extra/com.open-simulation-platform/"
HULLS = {
    "Semicircle": ["semicircle"],
    "Barge": [str(ROOT / "examples" / "ships" / "barge.xml")],
}


@pytest.fixture(scope="module")
def schema():
    return xmlschema.XMLSchema(str(SCHEMA))


@pytest.fixture(scope="module", params=sorted(HULLS))
def description(request, fmu_pack_binary, tmp_path_factory):
    """(text written beside the archive, the archive's copy) of one hull's FMU."""
    folder = tmp_path_factory.mktemp("osp-schema")
    archive = folder / f"{request.param}.fmu"
    subprocess.run([str(fmu_pack_binary), "pack", *HULLS[request.param], "-o", str(archive)],
                   check=True, capture_output=True)
    (beside,) = folder.glob("*_OspModelDescription.xml")
    with zipfile.ZipFile(archive) as z:
        copy = z.read(ARCHIVE_DIR + beside.name).decode()
    return beside.read_text(), copy


def test_the_description_validates_against_the_osp_is_schema(schema, description):
    text, copy = description
    assert copy == text
    errors = list(schema.iter_errors(text))
    assert errors == [], "\n".join(str(e) for e in errors[:3])
    assert "<LinearMechanicalPort " in text and "<Generic " in text


def test_the_schema_refuses_a_port_before_a_generic_group(schema, description):
    """The check can fail: the order of earlier releases (ports first) is invalid."""
    text, _ = description
    generic = re.search(r"    <Generic name=.*?\n    </Generic>\n", text, re.S).group(0)
    reordered = text.replace(generic, "").replace("  </VariableGroups>",
                                                  generic + "  </VariableGroups>")
    assert reordered != text
    assert not schema.is_valid(reordered)
