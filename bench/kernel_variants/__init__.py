"""Kernel variants measured by bench/kernel_profile.py: replacement shader files and the host data they read."""
