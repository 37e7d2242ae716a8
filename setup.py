"""Build the follower-force callback (controllers/follower.c) against MuJoCo's own headers."""

import os

import mujoco
from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "elastoactive.controllers._follower",
            sources=["controllers/follower.c"],
            include_dirs=[os.path.join(os.path.dirname(mujoco.__file__), "include")],
            extra_compile_args=["-O3", "-std=c11"],
        )
    ]
)
