#include <polyloc/gpu/compute.hpp>

#include <GLES3/gl31.h>

#include <fmt/core.h>

#include <cstring>
#include <vector>

namespace polyloc {
namespace {

std::string infoLog(GLuint object, bool program) {
  GLint n = 0;
  program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &n) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &n);
  std::vector<char> log(size_t(std::max(n, 1)), '\0');
  program ? glGetProgramInfoLog(object, n, nullptr, log.data()) : glGetShaderInfoLog(object, n, nullptr, log.data());
  return log.data();
}

}  // namespace

ComputeProgram::ComputeProgram(const GpuContext& gpu, std::string name, const std::string& source)
    : gpu_(gpu), name_(std::move(name)) {
  gpu_.makeCurrent();
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* src = source.c_str();
  glShaderSource(shader, 1, &src, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, false);
    glDeleteShader(shader);
    throw GpuError("gpu: compute shader '" + name_ + "' does not compile: " + log);
  }
  program_ = glCreateProgram();
  glAttachShader(program_, shader);
  glLinkProgram(program_);
  glDeleteShader(shader);
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program_, true);
    glDeleteProgram(program_);
    throw GpuError("gpu: compute program '" + name_ + "' does not link: " + log);
  }
  gpu_.check(("building compute program " + name_).c_str());
}

ComputeProgram::~ComputeProgram() {
  if (program_) glDeleteProgram(program_);
}

void ComputeProgram::use() const { glUseProgram(program_); }

void ComputeProgram::set(const char* uniform, float v) const {
  const GLint at = glGetUniformLocation(program_, uniform);
  if (at < 0) throw GpuError(fmt::format("gpu: program '{}' has no uniform '{}'", name_, uniform));
  glUniform1f(at, v);
}

void ComputeProgram::set(const char* uniform, uint32_t v) const {
  const GLint at = glGetUniformLocation(program_, uniform);
  if (at < 0) throw GpuError(fmt::format("gpu: program '{}' has no uniform '{}'", name_, uniform));
  glUniform1ui(at, v);
}

void ComputeProgram::dispatch(uint32_t gx, uint32_t gy, uint32_t gz) const {
  const GpuInfo& i = gpu_.info();
  if (gx > uint32_t(i.max_work_group_count[0]) || gy > uint32_t(i.max_work_group_count[1]) ||
      gz > uint32_t(i.max_work_group_count[2]))
    throw GpuError(fmt::format("gpu: '{}': {} x {} x {} work groups exceed the limit {} x {} x {}", name_, gx, gy, gz,
                               i.max_work_group_count[0], i.max_work_group_count[1], i.max_work_group_count[2]));
  glDispatchCompute(gx, gy, gz);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  gpu_.check(("dispatching " + name_).c_str());
}

StorageBuffer::StorageBuffer(const GpuContext& gpu, size_t bytes) : gpu_(gpu), bytes_(bytes) {
  if (bytes > size_t(gpu_.info().max_ssbo_bytes))
    throw GpuError(fmt::format("gpu: a buffer of {} bytes exceeds the largest storage block ({} bytes)", bytes,
                               gpu_.info().max_ssbo_bytes));
  glGenBuffers(1, &buffer_);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_);
  glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(std::max<size_t>(bytes, 4)), nullptr, GL_DYNAMIC_COPY);
  gpu_.check(fmt::format("allocating {} bytes of GPU memory", bytes).c_str());
}

StorageBuffer::~StorageBuffer() {
  if (buffer_) glDeleteBuffers(1, &buffer_);
}

void StorageBuffer::upload(const void* data, size_t bytes, size_t offset) {
  if (offset + bytes > bytes_)
    throw GpuError(fmt::format("gpu: upload of {} bytes at {} overruns a buffer of {}", bytes, offset, bytes_));
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, GLintptr(offset), GLsizeiptr(bytes), data);
  gpu_.check("uploading a storage buffer");
}

void StorageBuffer::download(void* data, size_t bytes, size_t offset) const {
  if (offset + bytes > bytes_)
    throw GpuError(fmt::format("gpu: read-back of {} bytes at {} overruns a buffer of {}", bytes, offset, bytes_));
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_);
  const void* p = glMapBufferRange(GL_SHADER_STORAGE_BUFFER, GLintptr(offset), GLsizeiptr(bytes), GL_MAP_READ_BIT);
  if (!p) gpu_.check("mapping a storage buffer for read-back");
  if (!p) throw GpuError("gpu: mapping a storage buffer for read-back failed");
  std::memcpy(data, p, bytes);
  glUnmapBuffer(GL_SHADER_STORAGE_BUFFER);
  gpu_.check("reading back a storage buffer");
}

void StorageBuffer::bind(unsigned binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer_); }

}  // namespace polyloc
