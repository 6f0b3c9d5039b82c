// Compute shaders (GLSL ES 3.10) and the shader storage buffers they read and write, on a
// GpuContext. A program is compiled once; a batch is uploads, one dispatch, one read-back.
// Errors are GpuError: a shader that does not compile names the program and carries the log.
#pragma once

#include <polyloc/gpu/context.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace polyloc {

class ComputeProgram {
 public:
  ComputeProgram(const GpuContext& gpu, std::string name, const std::string& source);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  void use() const;
  // Uniforms of the program in use (by name; a name the shader lacks is an error).
  void set(const char* uniform, float v) const;
  void set(const char* uniform, uint32_t v) const;
  // Runs `groups` work groups along x and waits until the storage writes are visible.
  void dispatch(uint32_t groups_x, uint32_t groups_y = 1, uint32_t groups_z = 1) const;
  const std::string& name() const { return name_; }

 private:
  const GpuContext& gpu_;
  std::string name_;
  unsigned program_ = 0;
};

class StorageBuffer {
 public:
  StorageBuffer(const GpuContext& gpu, size_t bytes);  // throws GpuError (out of GPU memory)
  ~StorageBuffer();
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  void upload(const void* data, size_t bytes, size_t offset = 0);
  void download(void* data, size_t bytes, size_t offset = 0) const;
  void bind(unsigned binding) const;  // to `layout(std430, binding = N) buffer`
  size_t size() const { return bytes_; }

 private:
  const GpuContext& gpu_;
  size_t bytes_ = 0;
  unsigned buffer_ = 0;
};

}  // namespace polyloc
