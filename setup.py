from glob import glob

from setuptools import find_packages, setup

package_name = 'contact_sim'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['data/*.npz']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
    ],
    install_requires=['setuptools', 'numpy', 'scipy', 'numba'],
    extras_require={'plot': ['matplotlib'], 'record': ['rosbags'], 'test': ['pytest'],
                    # sweeps on a Dask cluster (sweep(..., executor=Client.get_executor());
                    # bench/bench_cluster.py); tested with 2026.8.0, pinned in constraints.txt
                    'dask': ['dask[distributed]>=2026.8.0'],
                    'engines': ['mujoco', 'pybullet'], 'drake': ['drake']},
    zip_safe=True,
    maintainer='contact_sim developers',
    maintainer_email='dev@contact-sim.local',
    description='Azad-Featherstone compliant contact: impacts, restitution, and a ROS 2 node.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'contact-sim = contact_sim.cli:main',
            'contact_sim_node = contact_sim.ros.start:node_main',
            'contact_sim_record = contact_sim.ros.recorder:record_main',
        ],
    },
)
