"""Data: the object catalogue and the shipped world files (docs/simulator.md). A
package only so that setuptools installs the JSON files with the distribution."""
