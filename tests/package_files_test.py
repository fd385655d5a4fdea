"""The files an open scientific package carries say the same thing as the build: LICENSE is the GNU GPL version 3
(the license README names, GPL-3.0-or-later, forced by GSL's GPL and open to SUNDIALS', PETSc's and Eigen's
licenses), and CITATION.cff is Citation File Format 1.2.0 — its top-level keys among the format's, the required
ones present — with the license of README and the version of CMakeLists.txt's project(). Standard library only
(CITATION.cff's top-level keys and scalars are read line by line).

  package_files_test.py [REPOSITORY_ROOT]
"""
import os
import re
import sys
import unittest

ROOT = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))

# Citation File Format 1.2.0's top-level keys and the required ones (https://citation-file-format.github.io/1.2.0/schema).
CFF_KEYS = {"abstract", "authors", "cff-version", "commit", "contact", "date-released", "doi", "identifiers", "keywords",
            "license", "license-url", "message", "preferred-citation", "references", "repository",
            "repository-artifact", "repository-code", "title", "type", "url", "version"}
CFF_REQUIRED = {"authors", "cff-version", "message", "title"}


def read(name):
    with open(os.path.join(ROOT, name), encoding="utf-8") as f:
        return f.read()


def top_level(cff):
    """CITATION.cff's top-level keys with their scalar values (None for a block or list)."""
    keys = {}
    for line in cff.splitlines():
        m = re.match(r"^([A-Za-z][A-Za-z0-9-]*):\s*(.*?)\s*$", line)
        if m:
            value = m.group(2).strip('"')
            keys[m.group(1)] = value if value and value not in (">-", "|", ">") else None
    return keys


class PackageFiles(unittest.TestCase):
    def test_license_is_the_gpl_version_3(self):
        text = read("LICENSE")
        self.assertEqual(text.split("\n")[0].strip(), "GNU GENERAL PUBLIC LICENSE")
        self.assertIn("Version 3, 29 June 2007", text)
        self.assertIn("END OF TERMS AND CONDITIONS", text)  # the whole text, not a notice

    def test_readme_names_the_license(self):
        self.assertRegex(read("README.md"), r"## License\n[^#]*GPL-3\.0-or-later")

    def test_citation_is_cff_1_2_0_with_the_projects_version_and_license(self):
        keys = top_level(read("CITATION.cff"))
        self.assertLessEqual(set(keys), CFF_KEYS, "keys that Citation File Format 1.2.0 does not have")
        self.assertLessEqual(CFF_REQUIRED, set(keys), "keys that Citation File Format 1.2.0 requires")
        self.assertEqual(keys["cff-version"], "1.2.0")
        self.assertEqual(keys["license"], "GPL-3.0-or-later")
        version = re.search(r"project\(aggkit VERSION ([0-9.]+)", read("CMakeLists.txt")).group(1)
        self.assertEqual(keys["version"], version, "CITATION.cff's version is not CMakeLists.txt's project VERSION")


if __name__ == "__main__":
    unittest.main()
