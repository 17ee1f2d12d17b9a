// Sets an environment variable for a scope and puts back what was there: the solver reads
// BT_OPENCL_DEVICE, BT_OPENCL_SOLVE_PATH and BT_OPENCL_TRANSFERS when it is made.
#pragma once

#include <cstdlib>
#include <string>

namespace btocl::test {

class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        const char* was = std::getenv(name);
        m_had = was != nullptr;
        if (m_had) m_saved = was;
        setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (m_had)
            setenv(m_name.c_str(), m_saved.c_str(), 1);
        else
            unsetenv(m_name.c_str());
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string m_name, m_saved;
    bool m_had = false;
};

}  // namespace btocl::test
