// `syn-release build`: the release tar of a manifest's pipeline outputs (tools/release/release_contents.h
// lists what it holds).
#pragma once

#include <string>

#include "common/release_manifest.h"
#include "tools/release/release_contents.h"

namespace syn {

// The Debian versions of the numeric libraries the results depend on (dpkg-query; {} without dpkg).
// Package list: the ones whose code computes the numbers (Simbody, Ceres, Eigen, HDF5, SuiteSparse, g++).
[[nodiscard]] std::string DependencyVersionsJson();

// provenance.json: tool version, the dataset root the captures were read from (what `verify --rebuild`
// reads them from again) and the dependency versions. No time, host or user: same inputs, same bytes.
[[nodiscard]] std::string ProvenanceJson(const std::string& dataset_root);

// Collects the files of outputs/NAME, derives the datasheet and checksums, and writes the tar.
ReleaseSizes BuildRelease(const ReleaseManifest& manifest, const std::string& outputs_root, const std::string& dataset_root,
                          const std::string& tar_path);

}  // namespace syn
