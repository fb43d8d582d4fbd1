#!/usr/bin/env bash
# Self-check of the analytical Terzaghi, Mandel and Cryer solutions (postproc/analytical.py).
cd "$(dirname "$0")/../.."
exec "${PYTHON:-/usr/bin/python3}" postproc/test_analytical.py
